#include "mesh/gltf_export.h"

// Debian ships tinygltf compiled as a shared library (libtinygltf.so, see
// /usr/share/doc/libtinygltf-dev/README.Debian): we link it and include the
// declarations only, so TINYGLTF_IMPLEMENTATION is not defined here.
#include <tiny_gltf.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr const char* kGenerator = "sylva";
constexpr const char* kDefaultMaterial = "default";

// Appends `bytes` to the buffer as a new buffer view; returns its index.
int AddBufferView(const void* bytes, size_t size, int target, tinygltf::Model* model) {
  std::vector<unsigned char>& data = model->buffers[0].data;
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

tinygltf::Model MakeModel(const TriangleMesh& mesh, const GltfExportOptions& options) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = kGenerator;
  tinygltf::Value::Object extras;
  for (const auto& [key, value] : options.extras) extras[key] = tinygltf::Value(value);
  if (!extras.empty()) model.asset.extras = tinygltf::Value(extras);
  for (const Material& material : mesh.materials) model.materials.push_back(ToGltf(material));
  // A named scene: tinygltf 2.7 writes an empty scene object as null,
  // which its own loader then refuses.
  model.scenes.emplace_back();
  model.scenes[0].name = "tree";
  model.defaultScene = 0;
  if (mesh.NumTriangles() == 0) return model;
  model.buffers.emplace_back();
  const int positions = AddVec3Accessor(mesh.vertices, true, &model);
  const int normals = AddVec3Accessor(mesh.VertexNormals(), false, &model);
  model.meshes.push_back(MakeMesh(mesh, positions, normals, &model));
  tinygltf::Node node;
  node.mesh = 0;
  // -90 degrees about X, (x, y, z, w): world +Z becomes glTF +Y.
  if (options.y_up) node.rotation = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};
  model.nodes.push_back(node);
  model.scenes[0].nodes.push_back(0);
  return model;
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
  const tinygltf::Model model = MakeModel(mesh, options);
  AtomicWriteWith(path, [&](const fs::path& temp_path) {
    tinygltf::TinyGLTF writer;
    const bool ok = writer.WriteGltfSceneToFile(&model, temp_path.string(), /*embedImages=*/true,
                                                /*embedBuffers=*/true, /*prettyPrint=*/false,
                                                /*writeBinary=*/true);
    SYLVA_CHECK(ok) << "could not write " << path;
  });
}

TriangleMesh ReadGlb(const std::filesystem::path& path,
                     std::map<std::string, std::string>* asset_extras) {
  const std::string source = path.string();
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  SYLVA_CHECK_INPUT(loader.LoadBinaryFromFile(&model, &error, &warning, source), source)
      << "not a readable .glb: " << error;
  TriangleMesh mesh;
  std::map<int, int> first_vertex_of_accessor;
  for (const tinygltf::Mesh& gltf_mesh : model.meshes) {
    for (const tinygltf::Primitive& primitive : gltf_mesh.primitives) {
      ReadPrimitive(model, primitive, source, &first_vertex_of_accessor, &mesh);
    }
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

}  // namespace sylva
