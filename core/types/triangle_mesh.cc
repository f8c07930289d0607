#include "core/types/triangle_mesh.h"

#include "core/util/check.h"

namespace sylva {

int TriangleMesh::AddMaterial(const Material& material) {
  for (size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == material.name) return static_cast<int>(i);
  }
  materials.push_back(material);
  return static_cast<int>(materials.size()) - 1;
}

int TriangleMesh::AddVertex(const Eigen::Vector3f& position) {
  vertices.push_back(position);
  return NumVertices() - 1;
}

void TriangleMesh::AddTriangle(int a, int b, int c, int material_idx) {
  triangles.emplace_back(a, b, c);
  triangle_materials.push_back(material_idx);
}

void TriangleMesh::Append(const TriangleMesh& other) {
  const int vertex_offset = NumVertices();
  std::vector<int> material_map;
  for (const Material& material : other.materials) material_map.push_back(AddMaterial(material));
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (int t = 0; t < other.NumTriangles(); ++t) {
    const Eigen::Vector3i& tri = other.triangles[t];
    AddTriangle(tri.x() + vertex_offset, tri.y() + vertex_offset, tri.z() + vertex_offset,
                material_map.at(other.triangle_materials[t]));
  }
}

Box3d TriangleMesh::Bounds() const {
  Box3d box;
  for (const Eigen::Vector3f& v : vertices) box.extend(v.cast<double>());
  return box;
}

std::vector<Eigen::Vector3f> TriangleMesh::VertexNormals() const {
  std::vector<Eigen::Vector3f> normals(vertices.size(), Eigen::Vector3f::Zero());
  for (const Eigen::Vector3i& tri : triangles) {
    const Eigen::Vector3f n =
        (vertices[tri.y()] - vertices[tri.x()]).cross(vertices[tri.z()] - vertices[tri.x()]);
    for (int k = 0; k < 3; ++k) normals[tri[k]] += n;
  }
  for (Eigen::Vector3f& n : normals) {
    const float norm = n.norm();
    n = norm > 0 ? Eigen::Vector3f(n / norm) : Eigen::Vector3f::UnitZ();
  }
  return normals;
}

void TriangleMesh::Check() const {
  SYLVA_CHECK(triangle_materials.size() == triangles.size());
  for (const Eigen::Vector3f& v : vertices) SYLVA_CHECK(v.allFinite()) << "vertex not finite";
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      SYLVA_CHECK(triangles[t][k] >= 0 && triangles[t][k] < NumVertices())
          << "triangle " << t << " has vertex " << triangles[t][k];
    }
    SYLVA_CHECK(triangle_materials[t] >= 0 &&
                triangle_materials[t] < static_cast<int>(materials.size()))
        << "triangle " << t << " has material " << triangle_materials[t];
  }
}

}  // namespace sylva
