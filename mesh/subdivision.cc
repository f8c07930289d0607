#include "mesh/subdivision.h"

#include <chrono>
#include <sstream>
#include <vector>

#include "core/util/check.h"

namespace sylva {
namespace {

// Warren's even-vertex weights.
constexpr double kValence3Beta = 3.0 / 16.0;
constexpr double kBetaNumerator = 3.0 / 8.0;
// Odd-vertex weights: edge ends and opposite corners.
constexpr double kEdgeEndWeight = 3.0 / 8.0;
constexpr double kOppositeWeight = 1.0 / 8.0;

// Half-edge h = 3 t + c runs from corner c of triangle t to corner c + 1.
int Origin(const TriangleMesh& mesh, int h) { return mesh.triangles[h / 3][h % 3]; }
int Destination(const TriangleMesh& mesh, int h) { return mesh.triangles[h / 3][(h % 3 + 1) % 3]; }
int Next(int h) { return h - h % 3 + (h % 3 + 1) % 3; }
int Previous(int h) { return h - h % 3 + (h % 3 + 2) % 3; }

// Half-edges grouped by origin vertex, each half-edge's opposite twin and
// its undirected edge index.
struct HalfEdges {
  std::vector<int> out_begin;  // per vertex + 1: range into `out`
  std::vector<int> out;        // half-edge ids by origin, ascending within a vertex
  std::vector<int> twin;       // per half-edge
  std::vector<int> edge;       // per half-edge, shared with its twin
  int num_edges = 0;
};

void GroupByOrigin(const TriangleMesh& mesh, HalfEdges* he) {
  const int num_half_edges = 3 * mesh.NumTriangles();
  he->out_begin.assign(mesh.NumVertices() + 1, 0);
  for (int h = 0; h < num_half_edges; ++h) ++he->out_begin[Origin(mesh, h) + 1];
  for (int v = 0; v < mesh.NumVertices(); ++v) he->out_begin[v + 1] += he->out_begin[v];
  std::vector<int> fill(he->out_begin.begin(), he->out_begin.end() - 1);
  he->out.resize(num_half_edges);
  for (int h = 0; h < num_half_edges; ++h) he->out[fill[Origin(mesh, h)]++] = h;
}

// Counts of the ways the mesh fails to be a closed oriented 2-manifold.
struct Defects {
  int degenerate = 0;  // triangles repeating a vertex
  int boundary = 0;    // half-edges without an opposite twin
  int shared = 0;      // half-edges with a twin in the same direction, or several twins
  int fans = 0;        // vertices whose triangles form more than one fan
  bool Any() const { return degenerate + boundary + shared + fans > 0; }
};

void FindTwins(const TriangleMesh& mesh, HalfEdges* he, Defects* defects) {
  const int num_half_edges = 3 * mesh.NumTriangles();
  he->twin.assign(num_half_edges, -1);
  for (int h = 0; h < num_half_edges; ++h) {
    const int a = Origin(mesh, h), b = Destination(mesh, h);
    int twins = 0, same = 0;
    for (int k = he->out_begin[b]; k < he->out_begin[b + 1]; ++k) {
      if (Destination(mesh, he->out[k]) != a) continue;
      he->twin[h] = he->out[k];
      ++twins;
    }
    for (int k = he->out_begin[a]; k < he->out_begin[a + 1]; ++k) {
      same += Destination(mesh, he->out[k]) == b;
    }
    if (twins == 0) ++defects->boundary;
    if (twins > 1 || same > 1) ++defects->shared;
  }
}

// With every edge manifold, walks the fan around each vertex: it must visit
// all of the vertex's outgoing half-edges.
void CountFans(const TriangleMesh& mesh, const HalfEdges& he, Defects* defects) {
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    const int degree = he.out_begin[v + 1] - he.out_begin[v];
    if (degree == 0) continue;
    const int start = he.out[he.out_begin[v]];
    int h = start, steps = 0;
    do {
      h = he.twin[Previous(h)];
      ++steps;
    } while (h != start && steps <= degree);
    if (steps != degree) ++defects->fans;
  }
}

HalfEdges BuildHalfEdges(const TriangleMesh& mesh) {
  Defects defects;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    defects.degenerate += t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
  }
  HalfEdges he;
  GroupByOrigin(mesh, &he);
  FindTwins(mesh, &he, &defects);
  if (defects.boundary == 0 && defects.shared == 0) CountFans(mesh, he, &defects);
  SYLVA_CHECK_INPUT(!defects.Any(), "mesh")
      << "Loop subdivision needs a closed, consistently oriented 2-manifold; found "
      << defects.degenerate << " triangles repeating a vertex, " << defects.boundary
      << " boundary half-edges, " << defects.shared
      << " half-edges shared by 3+ triangles or misoriented, " << defects.fans
      << " vertices joining several fans";
  he.edge.assign(he.twin.size(), -1);
  for (size_t h = 0; h < he.twin.size(); ++h) {
    if (static_cast<int>(h) < he.twin[h]) he.edge[h] = he.edge[he.twin[h]] = he.num_edges++;
  }
  return he;
}

// Old vertices moved by Warren's even rule (their neighbours are the
// destinations of their outgoing half-edges).
void EvenVertices(const TriangleMesh& mesh, const HalfEdges& he,
                  std::vector<Eigen::Vector3f>* out) {
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    const int n = he.out_begin[v + 1] - he.out_begin[v];
    if (n == 0) {  // unused vertex: kept as is
      (*out)[v] = mesh.vertices[v];
      continue;
    }
    const double beta = n == 3 ? kValence3Beta : kBetaNumerator / n;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = he.out_begin[v]; k < he.out_begin[v + 1]; ++k) {
      sum += mesh.vertices[Destination(mesh, he.out[k])].cast<double>();
    }
    (*out)[v] = ((1 - n * beta) * mesh.vertices[v].cast<double>() + beta * sum).cast<float>();
  }
}

// New vertices on the edges (index NumVertices() + edge).
void OddVertices(const TriangleMesh& mesh, const HalfEdges& he, std::vector<Eigen::Vector3f>* out) {
  const auto position = [&](int v) { return mesh.vertices[v].cast<double>(); };
  for (size_t h = 0; h < he.twin.size(); ++h) {
    const int g = he.twin[h];
    if (static_cast<int>(h) > g) continue;
    const int a = Origin(mesh, h), b = Destination(mesh, h);
    const int c = Destination(mesh, Next(h)), d = Destination(mesh, Next(g));
    (*out)[mesh.NumVertices() + he.edge[h]] = (kEdgeEndWeight * (position(a) + position(b)) +
                                               kOppositeWeight * (position(c) + position(d)))
                                                  .cast<float>();
  }
}

TriangleMesh SubdivideOnce(const TriangleMesh& mesh) {
  const HalfEdges he = BuildHalfEdges(mesh);
  TriangleMesh fine;
  fine.materials = mesh.materials;
  fine.vertices.resize(mesh.NumVertices() + he.num_edges);
  EvenVertices(mesh, he, &fine.vertices);
  OddVertices(mesh, he, &fine.vertices);
  // Three corner triangles and the middle one, all with the parent's winding.
  fine.triangles.reserve(4 * mesh.triangles.size());
  fine.triangle_materials.reserve(4 * mesh.triangles.size());
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    const Eigen::Vector3i& v = mesh.triangles[t];
    const int base = mesh.NumVertices();
    const int m01 = base + he.edge[3 * t], m12 = base + he.edge[3 * t + 1],
              m20 = base + he.edge[3 * t + 2];
    fine.triangles.emplace_back(v[0], m01, m20);
    fine.triangles.emplace_back(v[1], m12, m01);
    fine.triangles.emplace_back(v[2], m20, m12);
    fine.triangles.emplace_back(m01, m12, m20);
    fine.triangle_materials.insert(fine.triangle_materials.end(), 4, mesh.triangle_materials[t]);
  }
  return fine;
}

// Signed enclosed volume by the divergence theorem (as CheckMesh, without
// its edge tables, which cost more than a subdivision level).
double SignedVolume(const TriangleMesh& mesh) {
  double volume = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    volume += a.dot(mesh.vertices[t[1]].cast<double>().cross(mesh.vertices[t[2]].cast<double>()));
  }
  return volume / 6;
}

}  // namespace

std::string LoopSubdivisionSummary::BriefReport() const {
  std::ostringstream out;
  out << "Loop subdivision: " << levels << " level(s), " << input_triangles << " -> " << triangles
      << " triangles, " << vertices << " vertices, volume x"
      << (input_volume != 0 ? volume / input_volume : 1.0) << " in " << seconds << " s.";
  return out.str();
}

TriangleMesh SubdivideLoop(const TriangleMesh& mesh, int levels, LoopSubdivisionSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  SYLVA_CHECK_INPUT(levels >= 0 && levels <= kMaxLoopLevels, "levels")
      << "must be in [0, " << kMaxLoopLevels << "], got " << levels;
  mesh.Check();
  TriangleMesh result = levels > 0 ? SubdivideOnce(mesh) : mesh;
  for (int level = 1; level < levels; ++level) result = SubdivideOnce(result);
  if (summary != nullptr) {
    summary->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary->levels = levels;
    summary->input_triangles = mesh.NumTriangles();
    summary->triangles = result.NumTriangles();
    summary->vertices = result.NumVertices();
    summary->input_volume = SignedVolume(mesh);
    summary->volume = SignedVolume(result);
  }
  return result;
}

}  // namespace sylva
