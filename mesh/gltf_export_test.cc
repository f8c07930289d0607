#include "mesh/gltf_export.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/io/mesh_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"
#include "mesh/branch_mesh.h"
#include "mesh/leaves.h"

namespace sylva {
namespace {

class GltfExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ =
        fs::temp_directory_path() /
        ("sylva_gltf_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path folder_;
};

// A bark tube plus two double-sided leaf triangles, and a material without triangles.
TriangleMesh TreeLikeMesh() {
  SkeletonGraph skeleton;
  int parent = skeleton.AddNode(Eigen::Vector3d::Zero(), 0.2, -1, 0);
  parent = skeleton.AddNode(Eigen::Vector3d(0.1, 0.0, 1.0), 0.15, parent, 0);
  skeleton.AddNode(Eigen::Vector3d(0.0, 0.2, 2.0), 0.1, parent, 0);
  skeleton.radius_source = "allometric prior";
  TriangleMesh mesh = MeshBranches(skeleton, BranchMeshOptions(), nullptr);
  const int leaves = mesh.AddMaterial({"leaves", Eigen::Vector3f(0.2f, 0.5f, 0.1f), true});
  const int a = mesh.AddVertex(Eigen::Vector3f(0.0f, 0.2f, 2.0f));
  const int b = mesh.AddVertex(Eigen::Vector3f(0.1f, 0.25f, 2.1f));
  const int c = mesh.AddVertex(Eigen::Vector3f(0.0f, 0.3f, 2.2f));
  const int d = mesh.AddVertex(Eigen::Vector3f(-0.1f, 0.25f, 2.1f));
  mesh.AddTriangle(a, b, c, leaves);
  mesh.AddTriangle(a, c, d, leaves);
  mesh.AddMaterial({"unused", Eigen::Vector3f(1.0f, 0.0f, 0.0f), false});
  return mesh;
}

const Material* FindMaterial(const TriangleMesh& mesh, const std::string& name) {
  for (const Material& m : mesh.materials) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

// Same geometry, triangles and per-triangle material names.
void ExpectSameMesh(const TriangleMesh& expected, const TriangleMesh& actual) {
  ASSERT_EQ(actual.NumVertices(), expected.NumVertices());
  ASSERT_EQ(actual.NumTriangles(), expected.NumTriangles());
  for (int i = 0; i < expected.NumVertices(); ++i) {
    EXPECT_LT((actual.vertices[i] - expected.vertices[i]).norm(), 1e-6f) << i;
  }
  for (int t = 0; t < expected.NumTriangles(); ++t) {
    EXPECT_EQ(actual.triangles[t], expected.triangles[t]) << t;
    EXPECT_EQ(actual.materials[actual.triangle_materials[t]].name,
              expected.materials[expected.triangle_materials[t]].name);
  }
  for (const Material& material : expected.materials) {
    const Material* back = FindMaterial(actual, material.name);
    ASSERT_NE(back, nullptr) << material.name;
    EXPECT_LT((back->diffuse_color - material.diffuse_color).norm(), 1e-6f) << material.name;
  }
}

// The JSON chunk of a .glb file (header: magic, version, length; then chunks).
nlohmann::json GlbJson(const fs::path& path) {
  const std::string bytes = ReadFileToString(path);
  uint32_t header[5];
  EXPECT_GE(bytes.size(), sizeof(header));
  std::memcpy(header, bytes.data(), sizeof(header));
  EXPECT_EQ(header[0], 0x46546C67u);  // "glTF"
  EXPECT_EQ(header[1], 2u);
  EXPECT_EQ(header[2], bytes.size());
  EXPECT_EQ(header[4], 0x4E4F534Au);  // "JSON"
  return nlohmann::json::parse(bytes.substr(sizeof(header), header[3]));
}

TEST_F(GltfExportTest, GlbRoundTripKeepsGeometryAndMaterials) {
  const TriangleMesh mesh = TreeLikeMesh();
  const fs::path path = folder_ / "tree.glb";
  GltfExportOptions options;
  options.extras["radius_source"] = "allometric prior";
  WriteGlb(path, mesh, options);
  std::map<std::string, std::string> extras;
  const TriangleMesh back = ReadGlb(path, &extras);
  ExpectSameMesh(mesh, back);
  EXPECT_TRUE(FindMaterial(back, "leaves")->double_sided);
  EXPECT_FALSE(FindMaterial(back, "bark")->double_sided);
  EXPECT_NE(FindMaterial(back, "unused"), nullptr);
  EXPECT_EQ(extras["generator"], "sylva");
  EXPECT_EQ(extras["radius_source"], "allometric prior");
  // Only the .glb is left in the folder (the temporary file was renamed).
  EXPECT_EQ(std::distance(fs::directory_iterator(folder_), fs::directory_iterator()), 1);
}

TEST_F(GltfExportTest, GlbHasOnePrimitivePerMaterialNormalsAndAYUpNode) {
  const TriangleMesh mesh = TreeLikeMesh();
  const fs::path path = folder_ / "tree.glb";
  WriteGlb(path, mesh);
  const nlohmann::json json = GlbJson(path);
  EXPECT_EQ(json["asset"]["version"], "2.0");
  EXPECT_EQ(json["asset"]["generator"], "sylva");
  ASSERT_EQ(json["meshes"].size(), 1u);
  ASSERT_EQ(json["meshes"][0]["primitives"].size(), 2u);  // "unused" has no triangles
  for (const nlohmann::json& primitive : json["meshes"][0]["primitives"]) {
    EXPECT_TRUE(primitive["attributes"].contains("NORMAL"));
    EXPECT_TRUE(primitive["attributes"].contains("POSITION"));
  }
  const nlohmann::json& position =
      json["accessors"][json["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
  EXPECT_EQ(position["count"], mesh.NumVertices());
  EXPECT_EQ(position["min"].size(), 3u);
  ASSERT_EQ(json["materials"].size(), 3u);
  EXPECT_EQ(json["materials"][0]["pbrMetallicRoughness"]["metallicFactor"], 0.0);
  // Colours as written by people: 0.36, not 0.36000001430511475.
  EXPECT_EQ(json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][0], 0.36);
  EXPECT_EQ(json["materials"][1]["doubleSided"], true);
  const std::vector<double> rotation = json["nodes"][0]["rotation"];
  EXPECT_NEAR(rotation[0], -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(rotation[3], std::sqrt(0.5), 1e-12);
}

TEST_F(GltfExportTest, ObjRoundTripMatchesTheGlb) {
  const TriangleMesh mesh = TreeLikeMesh();
  WriteObj(folder_ / "tree.obj", mesh);
  WriteGlb(folder_ / "tree.glb", mesh);
  const TriangleMesh from_obj = ReadObj(folder_ / "tree.obj");
  const TriangleMesh from_glb = ReadGlb(folder_ / "tree.glb");
  ExpectSameMesh(mesh, from_obj);
  ASSERT_EQ(from_obj.NumTriangles(), from_glb.NumTriangles());
  EXPECT_TRUE(FindMaterial(from_obj, "leaves")->double_sided);
}

TEST_F(GltfExportTest, EmptyMeshGivesAValidFile) {
  TriangleMesh mesh;
  mesh.AddMaterial({"bark"});
  WriteGlb(folder_ / "empty.glb", mesh);
  const TriangleMesh back = ReadGlb(folder_ / "empty.glb");
  EXPECT_EQ(back.NumTriangles(), 0);
  ASSERT_EQ(back.materials.size(), 1u);
  EXPECT_EQ(back.materials[0].name, "bark");
}

TEST_F(GltfExportTest, OverwritesAtomically) {
  const fs::path path = folder_ / "tree.glb";
  TriangleMesh small;
  small.AddMaterial({"bark"});
  WriteGlb(path, small);
  WriteGlb(path, TreeLikeMesh());
  EXPECT_EQ(ReadGlb(path).NumTriangles(), TreeLikeMesh().NumTriangles());
  EXPECT_EQ(std::distance(fs::directory_iterator(folder_), fs::directory_iterator()), 1);
}

TEST_F(GltfExportTest, BadFilesAreInputErrorsNamingTheFile) {
  const fs::path garbage = folder_ / "garbage.glb";
  std::ofstream(garbage) << "this is not a glb";
  try {
    ReadGlb(garbage);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), garbage.string());
  }
  EXPECT_THROW(ReadGlb(folder_ / "missing.glb"), InputError);
  // A truncated copy of a good file.
  WriteGlb(folder_ / "tree.glb", TreeLikeMesh());
  const std::string bytes = ReadFileToString(folder_ / "tree.glb");
  std::ofstream(folder_ / "cut.glb", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_THROW(ReadGlb(folder_ / "cut.glb"), InputError);
}

TEST_F(GltfExportTest, InvalidMeshesAndOptionsAreRefused) {
  TriangleMesh mesh = TreeLikeMesh();
  mesh.triangles[0].x() = mesh.NumVertices();
  EXPECT_THROW(WriteGlb(folder_ / "bad.glb", mesh), Error);
  GltfExportOptions options;
  options.extras[""] = "x";
  EXPECT_THROW(WriteGlb(folder_ / "bad.glb", TreeLikeMesh(), options), InputError);
  EXPECT_FALSE(fs::exists(folder_ / "bad.glb"));
}

// `count` leaves of `shape` at random positions, orientations and sizes.
LeafInstances RandomLeaves(const LeafShape& shape, int count) {
  LeafInstances leaves;
  leaves.shape = shape;
  leaves.material = {"leaves", Eigen::Vector3f(0.22f, 0.46f, 0.13f), true};
  RandomEngine rng(7);
  for (int i = 0; i < count; ++i) {
    LeafInstance leaf;
    leaf.translation = Eigen::Vector3f(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(1, 3));
    leaf.rotation =
        Eigen::Quaternionf(rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    leaf.scale = static_cast<float>(rng.Uniform(0.05, 0.1));
    leaves.instances.push_back(leaf);
  }
  return leaves;
}

TEST_F(GltfExportTest, InstancedLeavesReadBackAsTheBakedOnes) {
  TriangleMesh bark = TreeLikeMesh();
  const LeafInstances leaves = RandomLeaves(BuiltinLeafShape("ovate", 0.6), 200);
  const fs::path path = folder_ / "tree.glb";
  WriteGlb(path, bark, leaves);
  int64_t instances = 0;
  const TriangleMesh back = ReadGlb(path, nullptr, &instances);
  EXPECT_EQ(instances, 200);
  TriangleMesh expected = bark;
  expected.Append(leaves.Bake());
  ASSERT_EQ(back.NumTriangles(), expected.NumTriangles());
  ASSERT_EQ(back.NumVertices(), expected.NumVertices());
  for (int i = 0; i < expected.NumVertices(); ++i) {
    EXPECT_LT((back.vertices[i] - expected.vertices[i]).norm(), 1e-5f) << i;
  }
  EXPECT_TRUE(FindMaterial(back, "leaves")->double_sided);

  // Kept as instances: the bark's triangles, and the leaves as written.
  LeafInstances kept;
  const TriangleMesh bark_back = ReadGlbKeepingLeafInstances(path, &kept);
  EXPECT_EQ(bark_back.NumTriangles(), bark.NumTriangles());
  ASSERT_EQ(kept.instances.size(), 200u);
  EXPECT_EQ(kept.shape.triangles, leaves.shape.triangles);
  ASSERT_EQ(kept.shape.points.size(), leaves.shape.points.size());
  for (size_t i = 0; i < kept.shape.points.size(); ++i) {
    EXPECT_LT((kept.shape.points[i] - leaves.shape.points[i]).norm(), 1e-6f);
  }
  EXPECT_TRUE(kept.material.double_sided);
  EXPECT_LT((kept.material.diffuse_color - leaves.material.diffuse_color).norm(), 1e-6f);
  EXPECT_TRUE(kept.shape.uvs.empty() && kept.shape.texture.empty());
  TriangleMesh rebaked = bark_back;
  rebaked.Append(kept.Bake());
  for (int i = 0; i < expected.NumVertices(); i += 97) {
    EXPECT_LT((rebaked.vertices[i] - expected.vertices[i]).norm(), 1e-5f) << i;
  }

  const nlohmann::json json = GlbJson(path);
  ASSERT_EQ(json["extensionsUsed"].size(), 1u);
  EXPECT_EQ(json["extensionsUsed"][0], "EXT_mesh_gpu_instancing");
  EXPECT_FALSE(json.contains("extensionsRequired"));
  const nlohmann::json& node = json["nodes"][1];
  EXPECT_EQ(node["name"], "leaves");
  const nlohmann::json& attributes = node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
  for (const char* name : {"TRANSLATION", "ROTATION", "SCALE"}) {
    EXPECT_EQ(json["accessors"][attributes[name].get<int>()]["count"], 200) << name;
  }
  EXPECT_EQ(json["accessors"][attributes["ROTATION"].get<int>()]["type"], "VEC4");
  EXPECT_EQ(json["meshes"][node["mesh"].get<int>()]["name"], "leaves");

  // Instancing off: the same triangles baked, no extension.
  GltfExportOptions options;
  options.instance_leaves = false;
  WriteGlb(folder_ / "baked.glb", bark, leaves, options);
  EXPECT_FALSE(GlbJson(folder_ / "baked.glb").contains("extensionsUsed"));
  EXPECT_EQ(ReadGlb(folder_ / "baked.glb").NumTriangles(), expected.NumTriangles());
}

TEST_F(GltfExportTest, InstancingKeepsTenThousandLeavesSmall) {
  const LeafInstances leaves = RandomLeaves(BuiltinLeafShape("ovate", 0.6), 10000);
  WriteGlb(folder_ / "instanced.glb", TriangleMesh(), leaves);
  GltfExportOptions options;
  options.instance_leaves = false;
  WriteGlb(folder_ / "baked.glb", TriangleMesh(), leaves, options);
  const double instanced = static_cast<double>(fs::file_size(folder_ / "instanced.glb"));
  const double baked = static_cast<double>(fs::file_size(folder_ / "baked.glb"));
  // 40 bytes per leaf against 15 vertices x 24 + 14 triangles x 12 = 528.
  EXPECT_LT(instanced, 45.0 * 10000);
  EXPECT_GT(baked / instanced, 10.0);
}

TEST_F(GltfExportTest, ImageLeavesCarryAnAlphaMaskedTexture) {
  FloatImage image(16, 32, 4, 0.0f);
  for (int y = 0; y < 32; ++y) {
    for (int x = 4; x < 12; ++x) {
      image.at(x, y, 1) = 0.5f;
      image.at(x, y, 3) = 1.0f;
    }
  }
  const LeafInstances leaves = RandomLeaves(LeafShapeFromImage(image, "leaf.png"), 20);
  const fs::path path = folder_ / "tree.glb";
  WriteGlb(path, TreeLikeMesh(), leaves);
  const nlohmann::json json = GlbJson(path);
  ASSERT_EQ(json["images"].size(), 1u);
  ASSERT_EQ(json["textures"].size(), 1u);
  // A PNG in the binary chunk, not a base64 data URI.
  EXPECT_EQ(json["images"][0]["mimeType"], "image/png");
  EXPECT_TRUE(json["images"][0].contains("bufferView"));
  EXPECT_FALSE(json["images"][0].contains("uri"));
  const nlohmann::json& material = json["materials"].back();
  EXPECT_EQ(material["alphaMode"], "MASK");
  EXPECT_EQ(material["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
  const nlohmann::json& leaf_mesh = json["meshes"][json["nodes"][1]["mesh"].get<int>()];
  EXPECT_TRUE(leaf_mesh["primitives"][0]["attributes"].contains("TEXCOORD_0"));
  int64_t instances = 0;
  const TriangleMesh back = ReadGlb(path, nullptr, &instances);
  EXPECT_EQ(instances, 20);
  EXPECT_EQ(back.NumTriangles(), TreeLikeMesh().NumTriangles() + 40);
  // Kept as instances, the leaf keeps its UVs and its (8-bit) texture.
  LeafInstances kept;
  ReadGlbKeepingLeafInstances(path, &kept);
  EXPECT_EQ(kept.instances.size(), 20u);
  EXPECT_EQ(kept.shape.uvs, leaves.shape.uvs);
  ASSERT_EQ(kept.shape.texture.width(), 16);
  ASSERT_EQ(kept.shape.texture.height(), 32);
  ASSERT_EQ(kept.shape.texture.channels(), 4);
  EXPECT_NEAR(kept.shape.texture.at(5, 3, 1), 0.5f, 0.51f / 255);
  EXPECT_EQ(kept.shape.texture.at(5, 3, 3), 1.0f);
  EXPECT_EQ(kept.shape.texture.at(1, 3, 3), 0.0f);
}

}  // namespace
}  // namespace sylva
