// A triangle mesh with one material per triangle (bark, leaves, ...).
#ifndef SYLVA_CORE_TYPES_TRIANGLE_MESH_H_
#define SYLVA_CORE_TYPES_TRIANGLE_MESH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/geometry/box.h"

namespace sylva {

struct Material {
  std::string name;
  Eigen::Vector3f diffuse_color = Eigen::Vector3f(0.5f, 0.5f, 0.5f);  // linear RGB in [0, 1]
  bool double_sided = false;
};

class TriangleMesh {
 public:
  std::vector<Eigen::Vector3f> vertices;   // world units
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside
  std::vector<int> triangle_materials;     // index into materials, per triangle
  std::vector<Material> materials;

  int NumVertices() const { return static_cast<int>(vertices.size()); }
  int NumTriangles() const { return static_cast<int>(triangles.size()); }
  int AddMaterial(const Material& material);
  int AddVertex(const Eigen::Vector3f& position);
  void AddTriangle(int a, int b, int c, int material_idx);
  // Appends another mesh (its materials are matched by name or appended).
  void Append(const TriangleMesh& other);
  Box3d Bounds() const;
  // Per-vertex normals, area-weighted average of adjacent face normals.
  std::vector<Eigen::Vector3f> VertexNormals() const;
  // Throws Error on out-of-range indices or non-finite positions.
  void Check() const;
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_TRIANGLE_MESH_H_
