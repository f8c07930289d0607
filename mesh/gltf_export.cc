#include "mesh/gltf_export.h"

// Debian ships tinygltf compiled as a shared library (libtinygltf.so, see
// /usr/share/doc/libtinygltf-dev/README.Debian): we link it and include the
// declarations only, so TINYGLTF_IMPLEMENTATION is not defined here.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr const char* kGenerator = "sylva";
constexpr const char* kDefaultMaterial = "default";

// Appends `bytes` to the buffer as a new buffer view; returns its index.
// `target` 0 = none (instance attributes, images).
int AddBufferView(const void* bytes, size_t size, int target, tinygltf::Model* model) {
  std::vector<unsigned char>& data = model->buffers[0].data;
  // Views start 4-byte aligned, as float and uint32 accessors need (an
  // embedded PNG may have any length).
  data.resize((data.size() + 3) / 4 * 4, 0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  const unsigned char* begin = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), begin, begin + size);
  model->bufferViews.push_back(view);
  return static_cast<int>(model->bufferViews.size()) - 1;
}

int AddAccessor(int view, int component_type, int type, size_t count, tinygltf::Model* model) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  model->accessors.push_back(accessor);
  return static_cast<int>(model->accessors.size()) - 1;
}

// A float VEC3 attribute accessor over `values`; with min/max if `bounds`
// (glTF requires them for POSITION).
int AddVec3Accessor(const std::vector<Eigen::Vector3f>& values, bool bounds,
                    tinygltf::Model* model) {
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "packed Vector3f");
  const int view = AddBufferView(values.data(), values.size() * sizeof(Eigen::Vector3f),
                                 TINYGLTF_TARGET_ARRAY_BUFFER, model);
  const int accessor =
      AddAccessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, values.size(), model);
  if (bounds) {
    Eigen::Vector3f lo = values[0], hi = values[0];
    for (const Eigen::Vector3f& v : values) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    model->accessors[accessor].minValues = {lo.x(), lo.y(), lo.z()};
    model->accessors[accessor].maxValues = {hi.x(), hi.y(), hi.z()};
  }
  return accessor;
}

// The double nearest the shortest decimal that reads back as `value`, so
// the JSON says 0.36, not 0.36000001430511475.
double ShortestDouble(float value) {
  char text[32];
  for (int digits = 6; digits < 9; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtof(text, nullptr) == value) return std::strtod(text, nullptr);
  }
  return value;
}

tinygltf::Material ToGltf(const Material& material) {
  tinygltf::Material out;
  out.name = material.name;
  const Eigen::Vector3f& c = material.diffuse_color;
  out.pbrMetallicRoughness.baseColorFactor = {ShortestDouble(c.x()), ShortestDouble(c.y()),
                                              ShortestDouble(c.z()), 1.0};
  out.pbrMetallicRoughness.metallicFactor = 0.0;
  out.pbrMetallicRoughness.roughnessFactor = 1.0;
  out.doubleSided = material.double_sided;
  return out;
}

// One primitive per material with triangles, sharing the vertex accessors.
tinygltf::Mesh MakeMesh(const TriangleMesh& mesh, int positions, int normals,
                        tinygltf::Model* model) {
  std::vector<std::vector<uint32_t>> indices(mesh.materials.size());
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    for (int k = 0; k < 3; ++k) indices[mesh.triangle_materials[t]].push_back(mesh.triangles[t][k]);
  }
  tinygltf::Mesh out;
  out.name = "tree";
  for (size_t m = 0; m < indices.size(); ++m) {
    if (indices[m].empty()) continue;
    const int view = AddBufferView(indices[m].data(), indices[m].size() * sizeof(uint32_t),
                                   TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, model);
    tinygltf::Primitive primitive;
    primitive.attributes = {{"POSITION", positions}, {"NORMAL", normals}};
    primitive.indices = AddAccessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                    TINYGLTF_TYPE_SCALAR, indices[m].size(), model);
    primitive.material = static_cast<int>(m);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    out.primitives.push_back(primitive);
  }
  return out;
}

constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
// Alpha below this is cut away on image leaves (alphaMode MASK).
constexpr double kAlphaCutoff = 0.5;

// -90 degrees about X, (x, y, z, w): world +Z becomes glTF +Y.
void SetYUp(const GltfExportOptions& options, tinygltf::Node* node) {
  if (options.y_up) node->rotation = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};
}

tinygltf::Model EmptyModel(const GltfExportOptions& options) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = kGenerator;
  tinygltf::Value::Object extras;
  for (const auto& [key, value] : options.extras) extras[key] = tinygltf::Value(value);
  if (!extras.empty()) model.asset.extras = tinygltf::Value(extras);
  // A named scene: tinygltf 2.7 writes an empty scene object as null,
  // which its own loader then refuses.
  model.scenes.emplace_back();
  model.scenes[0].name = "tree";
  model.defaultScene = 0;
  model.buffers.emplace_back();
  return model;
}

void AddTreeMesh(const TriangleMesh& mesh, const GltfExportOptions& options,
                 tinygltf::Model* model) {
  for (const Material& material : mesh.materials) model->materials.push_back(ToGltf(material));
  if (mesh.NumTriangles() == 0) return;
  const int positions = AddVec3Accessor(mesh.vertices, true, model);
  const int normals = AddVec3Accessor(mesh.VertexNormals(), false, model);
  model->meshes.push_back(MakeMesh(mesh, positions, normals, model));
  tinygltf::Node node;
  node.name = "tree";
  node.mesh = static_cast<int>(model->meshes.size()) - 1;
  SetYUp(options, &node);
  model->nodes.push_back(node);
  model->scenes[0].nodes.push_back(static_cast<int>(model->nodes.size()) - 1);
}

// PNG bytes of an 8-bit RGBA image: tinygltf's own encoder (stb), with a
// file-system callback that keeps the "file" in memory.
std::vector<unsigned char> EncodePng(const tinygltf::Image& image) {
  std::vector<unsigned char> png;
  tinygltf::FsCallbacks memory{};
  memory.WriteWholeFile = [](std::string*, const std::string&,
                             const std::vector<unsigned char>& contents, void* user_data) {
    *static_cast<std::vector<unsigned char>*>(user_data) = contents;
    return true;
  };
  memory.user_data = &png;
  const std::string folder, name = "leaf.png";
  std::string uri;
  SYLVA_CHECK(
      tinygltf::WriteImageData(&folder, &name, &image, /*embedImages=*/false, &uri, &memory) &&
      !png.empty())
      << "could not encode the leaf texture as PNG";
  return png;
}

// The RGBA texture as an 8-bit PNG in the binary buffer (a data URI would be
// base64 text in the JSON, which the validator warns against in a .glb) and
// a texture using it; returns the texture index.
int AddTexture(const FloatImage& rgba, tinygltf::Model* model) {
  tinygltf::Image pixels;
  pixels.width = rgba.width();
  pixels.height = rgba.height();
  pixels.component = 4;
  pixels.bits = 8;
  pixels.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  pixels.image.resize(rgba.values().size());
  for (size_t i = 0; i < pixels.image.size(); ++i) {
    pixels.image[i] =
        static_cast<unsigned char>(std::lround(255.0f * std::clamp(rgba.values()[i], 0.0f, 1.0f)));
  }
  const std::vector<unsigned char> png = EncodePng(pixels);
  tinygltf::Image image;
  image.name = "leaf";
  image.mimeType = "image/png";
  image.bufferView = AddBufferView(png.data(), png.size(), 0, model);
  model->images.push_back(image);
  tinygltf::Texture texture;
  texture.source = static_cast<int>(model->images.size()) - 1;
  model->textures.push_back(texture);
  return static_cast<int>(model->textures.size()) - 1;
}

// The leaf shape as a mesh of one primitive; returns the mesh index.
int AddLeafMesh(const LeafInstances& leaves, tinygltf::Model* model) {
  const LeafShape& shape = leaves.shape;
  std::vector<Eigen::Vector3f> positions, normals;
  for (const Eigen::Vector2f& p : shape.points) {
    positions.emplace_back(p.x(), p.y(), 0.0f);
    normals.emplace_back(0.0f, 0.0f, 1.0f);
  }
  std::vector<uint32_t> indices;
  for (const Eigen::Vector3i& t : shape.triangles)
    indices.insert(indices.end(), {uint32_t(t[0]), uint32_t(t[1]), uint32_t(t[2])});
  tinygltf::Primitive primitive;
  primitive.attributes = {{"POSITION", AddVec3Accessor(positions, true, model)},
                          {"NORMAL", AddVec3Accessor(normals, false, model)}};
  tinygltf::Material material = ToGltf(leaves.material);
  if (!shape.uvs.empty()) {
    const int view = AddBufferView(shape.uvs.data(), shape.uvs.size() * sizeof(Eigen::Vector2f),
                                   TINYGLTF_TARGET_ARRAY_BUFFER, model);
    primitive.attributes["TEXCOORD_0"] = AddAccessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                     TINYGLTF_TYPE_VEC2, shape.uvs.size(), model);
  }
  if (!shape.texture.empty()) {
    material.pbrMetallicRoughness.baseColorTexture.index = AddTexture(shape.texture, model);
    material.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
    material.alphaMode = "MASK";
    material.alphaCutoff = kAlphaCutoff;
  }
  model->materials.push_back(material);
  const int view = AddBufferView(indices.data(), indices.size() * sizeof(uint32_t),
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, model);
  primitive.indices = AddAccessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                  indices.size(), model);
  primitive.material = static_cast<int>(model->materials.size()) - 1;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = "leaves";
  mesh.primitives.push_back(primitive);
  model->meshes.push_back(mesh);
  return static_cast<int>(model->meshes.size()) - 1;
}

// A float accessor of `components` per instance, no buffer view target
// (instance attributes are not vertex attributes).
int AddInstanceAccessor(const std::vector<float>& values, int type, int components,
                        tinygltf::Model* model) {
  const int view = AddBufferView(values.data(), values.size() * sizeof(float), 0, model);
  return AddAccessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, type, values.size() / components, model);
}

void AddInstancedLeaves(const LeafInstances& leaves, const GltfExportOptions& options,
                        tinygltf::Model* model) {
  if (leaves.instances.empty()) return;
  leaves.shape.Check();
  tinygltf::Node node;
  node.name = "leaves";
  node.mesh = AddLeafMesh(leaves, model);
  SetYUp(options, &node);
  std::vector<float> translation, rotation, scale;
  for (const LeafInstance& leaf : leaves.instances) {
    translation.insert(translation.end(),
                       {leaf.translation.x(), leaf.translation.y(), leaf.translation.z()});
    const Eigen::Quaternionf q = leaf.rotation.normalized();
    rotation.insert(rotation.end(), {q.x(), q.y(), q.z(), q.w()});
    scale.insert(scale.end(), {leaf.scale, leaf.scale, leaf.scale});
  }
  tinygltf::Value::Object attributes;
  attributes["TRANSLATION"] =
      tinygltf::Value(AddInstanceAccessor(translation, TINYGLTF_TYPE_VEC3, 3, model));
  attributes["ROTATION"] =
      tinygltf::Value(AddInstanceAccessor(rotation, TINYGLTF_TYPE_VEC4, 4, model));
  attributes["SCALE"] = tinygltf::Value(AddInstanceAccessor(scale, TINYGLTF_TYPE_VEC3, 3, model));
  tinygltf::Value::Object extension;
  extension["attributes"] = tinygltf::Value(attributes);
  node.extensions[kInstancing] = tinygltf::Value(extension);
  model->nodes.push_back(node);
  model->scenes[0].nodes.push_back(static_cast<int>(model->nodes.size()) - 1);
  model->extensionsUsed.push_back(kInstancing);
}

// tinygltf writes an empty buffer as an invalid one: drop it.
void DropEmptyBuffer(tinygltf::Model* model) {
  if (model->buffers[0].data.empty()) model->buffers.clear();
}

void WriteModel(const std::filesystem::path& path, const tinygltf::Model& model) {
  AtomicWriteWith(path, [&](const fs::path& temp_path) {
    tinygltf::TinyGLTF writer;
    const bool ok = writer.WriteGltfSceneToFile(&model, temp_path.string(), /*embedImages=*/true,
                                                /*embedBuffers=*/true, /*prettyPrint=*/false,
                                                /*writeBinary=*/true);
    SYLVA_CHECK(ok) << "could not write " << path;
  });
}

// ---- Reading ----

// Reads accessor `index` element by element: `visit(k, bytes)` for k = 0..count-1.
template <typename Visit>
void ForEachElement(const tinygltf::Model& model, int index, const std::string& source,
                    Visit&& visit) {
  SYLVA_CHECK_INPUT(index >= 0 && index < static_cast<int>(model.accessors.size()), source)
      << "accessor " << index << " does not exist";
  const tinygltf::Accessor& accessor = model.accessors[index];
  SYLVA_CHECK_INPUT(!accessor.sparse.isSparse && accessor.bufferView >= 0 &&
                        accessor.bufferView < static_cast<int>(model.bufferViews.size()),
                    source)
      << "accessor " << index << " has no plain buffer view (sparse accessors unsupported)";
  const tinygltf::BufferView& view = model.bufferViews[accessor.bufferView];
  SYLVA_CHECK_INPUT(view.buffer >= 0 && view.buffer < static_cast<int>(model.buffers.size()),
                    source)
      << "buffer view " << accessor.bufferView << " has no buffer";
  const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
  const int stride = accessor.ByteStride(view);
  const size_t element = tinygltf::GetComponentSizeInBytes(accessor.componentType) *
                         tinygltf::GetNumComponentsInType(accessor.type);
  const size_t begin = view.byteOffset + accessor.byteOffset;
  SYLVA_CHECK_INPUT(
      stride > 0 && (accessor.count == 0 || (begin + stride * (accessor.count - 1) + element <=
                                                 view.byteOffset + view.byteLength &&
                                             view.byteOffset + view.byteLength <= data.size())),
      source)
      << "accessor " << index << " reaches beyond its buffer";
  for (size_t k = 0; k < accessor.count; ++k) visit(k, data.data() + begin + k * stride);
}

// Appends the float VEC3 positions of accessor `index`; returns the first vertex.
int ReadPositions(const tinygltf::Model& model, int index, const std::string& source,
                  TriangleMesh* mesh) {
  const tinygltf::Accessor& accessor = model.accessors.at(index);
  SYLVA_CHECK_INPUT(accessor.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT &&
                        accessor.type == TINYGLTF_TYPE_VEC3,
                    source)
      << "POSITION accessor " << index << " is not float VEC3";
  const int first = mesh->NumVertices();
  ForEachElement(model, index, source, [&](size_t, const unsigned char* bytes) {
    float xyz[3];
    std::memcpy(xyz, bytes, sizeof(xyz));
    mesh->AddVertex(Eigen::Vector3f(xyz[0], xyz[1], xyz[2]));
  });
  return first;
}

std::vector<int> ReadIndices(const tinygltf::Model& model, int index, const std::string& source) {
  const int type = model.accessors.at(index).componentType;
  SYLVA_CHECK_INPUT(model.accessors[index].type == TINYGLTF_TYPE_SCALAR &&
                        (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT),
                    source)
      << "index accessor " << index << " is not an unsigned integer scalar";
  std::vector<int> indices;
  ForEachElement(model, index, source, [&](size_t, const unsigned char* bytes) {
    uint32_t value = 0;
    if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
      value = bytes[0];
    } else if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      uint16_t v16;
      std::memcpy(&v16, bytes, sizeof(v16));
      value = v16;
    } else {
      std::memcpy(&value, bytes, sizeof(value));
    }
    indices.push_back(static_cast<int>(value));
  });
  return indices;
}

Material FromGltf(const tinygltf::Material& material, int index) {
  Material out;
  out.name = material.name.empty() ? "material_" + std::to_string(index) : material.name;
  const std::vector<double>& c = material.pbrMetallicRoughness.baseColorFactor;
  if (c.size() >= 3) out.diffuse_color = Eigen::Vector3d(c[0], c[1], c[2]).cast<float>();
  out.double_sided = material.doubleSided;
  return out;
}

void ReadPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                   const std::string& source, std::map<int, int>* first_vertex_of_accessor,
                   TriangleMesh* mesh) {
  SYLVA_CHECK_INPUT(primitive.mode == TINYGLTF_MODE_TRIANGLES || primitive.mode == -1, source)
      << "primitive mode " << primitive.mode << " is not TRIANGLES";
  const auto position = primitive.attributes.find("POSITION");
  SYLVA_CHECK_INPUT(position != primitive.attributes.end(), source)
      << "a primitive has no POSITION";
  const int accessor = position->second;
  if (first_vertex_of_accessor->count(accessor) == 0) {
    (*first_vertex_of_accessor)[accessor] = ReadPositions(model, accessor, source, mesh);
  }
  const int first = first_vertex_of_accessor->at(accessor);
  const int count = static_cast<int>(model.accessors[accessor].count);
  std::vector<int> indices;
  if (primitive.indices >= 0) {
    indices = ReadIndices(model, primitive.indices, source);
  } else {
    for (int i = 0; i < count; ++i) indices.push_back(i);
  }
  SYLVA_CHECK_INPUT(indices.size() % 3 == 0, source) << "index count is not a multiple of 3";
  const int material =
      primitive.material >= 0 && primitive.material < static_cast<int>(model.materials.size())
          ? mesh->AddMaterial(FromGltf(model.materials[primitive.material], primitive.material))
          : mesh->AddMaterial({kDefaultMaterial});
  for (size_t k = 0; k < indices.size(); k += 3) {
    for (int j = 0; j < 3; ++j) {
      SYLVA_CHECK_INPUT(indices[k + j] < count, source)
          << "index " << indices[k + j] << " beyond " << count << " vertices";
    }
    mesh->AddTriangle(first + indices[k], first + indices[k + 1], first + indices[k + 2], material);
  }
}

// Float elements of `components` per element from accessor `index` (-1 =
// absent: empty).
std::vector<float> ReadFloats(const tinygltf::Model& model, int index, int type, int components,
                              const std::string& source) {
  std::vector<float> values;
  if (index < 0) return values;
  SYLVA_CHECK_INPUT(index < static_cast<int>(model.accessors.size()) &&
                        model.accessors[index].componentType == TINYGLTF_COMPONENT_TYPE_FLOAT &&
                        model.accessors[index].type == type,
                    source)
      << "instance accessor " << index << " is not float with " << components << " components";
  values.resize(model.accessors[index].count * components);
  ForEachElement(model, index, source, [&](size_t k, const unsigned char* bytes) {
    std::memcpy(values.data() + k * components, bytes, components * sizeof(float));
  });
  return values;
}

int InstanceAttribute(const tinygltf::Value& extension, const char* name) {
  const tinygltf::Value& attributes = extension.Get("attributes");
  if (!attributes.IsObject() || !attributes.Has(name) || !attributes.Get(name).IsInt()) return -1;
  return attributes.Get(name).Get<int>();
}

// The instance transforms of an EXT_mesh_gpu_instancing node (absent
// attributes: identity).
std::vector<LeafInstance> ReadInstances(const tinygltf::Model& model,
                                        const tinygltf::Value& extension,
                                        const std::string& source) {
  const std::vector<float> t =
      ReadFloats(model, InstanceAttribute(extension, "TRANSLATION"), TINYGLTF_TYPE_VEC3, 3, source);
  const std::vector<float> r =
      ReadFloats(model, InstanceAttribute(extension, "ROTATION"), TINYGLTF_TYPE_VEC4, 4, source);
  const std::vector<float> s =
      ReadFloats(model, InstanceAttribute(extension, "SCALE"), TINYGLTF_TYPE_VEC3, 3, source);
  const size_t count = std::max({t.size() / 3, r.size() / 4, s.size() / 3});
  SYLVA_CHECK_INPUT((t.empty() || t.size() == 3 * count) && (r.empty() || r.size() == 4 * count) &&
                        (s.empty() || s.size() == 3 * count),
                    source)
      << "instance attributes of different counts";
  std::vector<LeafInstance> instances(count);
  for (size_t k = 0; k < count; ++k) {
    if (!t.empty())
      instances[k].translation = Eigen::Vector3f(t[3 * k], t[3 * k + 1], t[3 * k + 2]);
    if (!r.empty()) {
      instances[k].rotation =
          Eigen::Quaternionf(r[4 * k + 3], r[4 * k], r[4 * k + 1], r[4 * k + 2]);
    }
    // Non-uniform scales are not representable in LeafInstance; read x.
    if (!s.empty()) instances[k].scale = s[3 * k];
  }
  return instances;
}

// Appends `prototype` once per instance, transformed.
void AppendInstances(const TriangleMesh& prototype, const std::vector<LeafInstance>& instances,
                     TriangleMesh* mesh) {
  TriangleMesh copies;
  copies.materials = prototype.materials;
  copies.vertices.reserve(prototype.vertices.size() * instances.size());
  for (const LeafInstance& instance : instances) {
    const Eigen::Matrix3f rotation = instance.rotation.normalized().toRotationMatrix();
    const int first = copies.NumVertices();
    for (const Eigen::Vector3f& v : prototype.vertices) {
      copies.vertices.push_back(instance.translation + instance.scale * (rotation * v));
    }
    for (int t = 0; t < prototype.NumTriangles(); ++t) {
      copies.triangles.push_back(prototype.triangles[t] + Eigen::Vector3i::Constant(first));
      copies.triangle_materials.push_back(prototype.triangle_materials[t]);
    }
  }
  mesh->Append(copies);
}

}  // namespace

void GltfExportOptions::Check() const {
  for (const auto& entry : extras) {
    SYLVA_CHECK_INPUT(!entry.first.empty(), "GltfExport.extras") << "keys must not be empty";
  }
}

void WriteGlb(const std::filesystem::path& path, const TriangleMesh& mesh,
              const GltfExportOptions& options) {
  options.Check();
  mesh.Check();
  tinygltf::Model model = EmptyModel(options);
  AddTreeMesh(mesh, options, &model);
  DropEmptyBuffer(&model);
  WriteModel(path, model);
}

void WriteGlb(const std::filesystem::path& path, const TriangleMesh& mesh,
              const LeafInstances& leaves, const GltfExportOptions& options) {
  if (!options.instance_leaves) {
    TriangleMesh baked = mesh;
    baked.Append(leaves.Bake());
    WriteGlb(path, baked, options);
    return;
  }
  options.Check();
  mesh.Check();
  tinygltf::Model model = EmptyModel(options);
  AddTreeMesh(mesh, options, &model);
  AddInstancedLeaves(leaves, options, &model);
  DropEmptyBuffer(&model);
  WriteModel(path, model);
}

namespace {

// The leaf shape of an instanced mesh (`prototype`: its triangles as read):
// the positions' (x, y) in the leaf frame, and where its first primitive has
// TEXCOORD_0 and a base colour texture decoded as 8-bit RGBA, those.
LeafInstances LeafInstancesFromGlb(const tinygltf::Model& model, const tinygltf::Mesh& mesh,
                                   const TriangleMesh& prototype, const std::string& source) {
  LeafInstances leaves;
  leaves.shape.name = mesh.name;
  for (const Eigen::Vector3f& v : prototype.vertices)
    leaves.shape.points.emplace_back(v.x(), v.y());
  leaves.shape.triangles = prototype.triangles;
  if (!prototype.triangle_materials.empty()) {
    leaves.material = prototype.materials[prototype.triangle_materials[0]];
  }
  const tinygltf::Primitive& primitive = mesh.primitives.front();
  const auto uvs = primitive.attributes.find("TEXCOORD_0");
  if (uvs == primitive.attributes.end() || primitive.material < 0 ||
      primitive.material >= static_cast<int>(model.materials.size())) {
    return leaves;
  }
  const int texture =
      model.materials[primitive.material].pbrMetallicRoughness.baseColorTexture.index;
  if (texture < 0 || texture >= static_cast<int>(model.textures.size())) return leaves;
  const int image_idx = model.textures[texture].source;
  if (image_idx < 0 || image_idx >= static_cast<int>(model.images.size())) return leaves;
  const tinygltf::Image& image = model.images[image_idx];
  const std::vector<float> uv = ReadFloats(model, uvs->second, TINYGLTF_TYPE_VEC2, 2, source);
  if (image.component != 4 || image.bits != 8 || uv.size() != 2 * leaves.shape.points.size() ||
      image.image.size() != size_t(4) * image.width * image.height) {
    return leaves;
  }
  for (size_t k = 0; k < leaves.shape.points.size(); ++k) {
    leaves.shape.uvs.emplace_back(uv[2 * k], uv[2 * k + 1]);
  }
  leaves.shape.texture = FloatImage(image.width, image.height, 4);
  for (size_t i = 0; i < image.image.size(); ++i) {
    leaves.shape.texture.values()[i] = image.image[i] / 255.0f;
  }
  return leaves;
}

// ReadGlb; with `leaves`, the first instanced node's mesh and transforms
// go there instead of being expanded.
TriangleMesh ReadGlbImpl(const std::filesystem::path& path,
                         std::map<std::string, std::string>* asset_extras, int64_t* num_instances,
                         LeafInstances* leaves) {
  const std::string source = path.string();
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  SYLVA_CHECK_INPUT(loader.LoadBinaryFromFile(&model, &error, &warning, source), source)
      << "not a readable .glb: " << error;
  TriangleMesh mesh;
  std::set<int> instanced_meshes;
  for (const tinygltf::Node& node : model.nodes) {
    if (node.mesh >= 0 && node.extensions.count(kInstancing)) instanced_meshes.insert(node.mesh);
  }
  std::map<int, int> first_vertex_of_accessor;
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    if (instanced_meshes.count(static_cast<int>(m))) continue;
    for (const tinygltf::Primitive& primitive : model.meshes[m].primitives) {
      ReadPrimitive(model, primitive, source, &first_vertex_of_accessor, &mesh);
    }
  }
  if (num_instances != nullptr) *num_instances = 0;
  for (const tinygltf::Node& node : model.nodes) {
    if (node.mesh < 0 || node.extensions.count(kInstancing) == 0) continue;
    SYLVA_CHECK_INPUT(node.mesh < static_cast<int>(model.meshes.size()), source)
        << "node mesh " << node.mesh << " does not exist";
    TriangleMesh prototype;
    std::map<int, int> first_vertex;
    for (const tinygltf::Primitive& primitive : model.meshes[node.mesh].primitives) {
      ReadPrimitive(model, primitive, source, &first_vertex, &prototype);
    }
    std::vector<LeafInstance> instances =
        ReadInstances(model, node.extensions.at(kInstancing), source);
    if (num_instances != nullptr) *num_instances += static_cast<int64_t>(instances.size());
    if (leaves != nullptr && leaves->instances.empty() && !instances.empty()) {
      *leaves = LeafInstancesFromGlb(model, model.meshes[node.mesh], prototype, source);
      leaves->instances = std::move(instances);
      continue;
    }
    AppendInstances(prototype, instances, &mesh);
  }
  // Materials no primitive used still come back, in the file's order of appearance.
  for (size_t m = 0; m < model.materials.size(); ++m) {
    mesh.AddMaterial(FromGltf(model.materials[m], static_cast<int>(m)));
  }
  if (asset_extras != nullptr) {
    asset_extras->clear();
    (*asset_extras)["generator"] = model.asset.generator;
    const tinygltf::Value& extras = model.asset.extras;
    if (extras.IsObject()) {
      for (const std::string& key : extras.Keys()) {
        if (extras.Get(key).IsString()) (*asset_extras)[key] = extras.Get(key).Get<std::string>();
      }
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh ReadGlb(const std::filesystem::path& path,
                     std::map<std::string, std::string>* asset_extras, int64_t* num_instances) {
  return ReadGlbImpl(path, asset_extras, num_instances, nullptr);
}

TriangleMesh ReadGlbKeepingLeafInstances(const std::filesystem::path& path, LeafInstances* leaves) {
  SYLVA_CHECK(leaves != nullptr);
  return ReadGlbImpl(path, nullptr, nullptr, leaves);
}

}  // namespace sylva
