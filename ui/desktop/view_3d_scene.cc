#include "ui/desktop/view_3d_scene.h"

#include <QColor>
#include <QStringList>
#include <algorithm>
#include <exception>
#include <filesystem>

#include "core/io/mesh_io.h"
#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "core/types/density_grid.h"
#include "core/types/skeleton_graph.h"
#include "ui/pipeline/project.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// Voxels at least this opaque are drawn, at most kMaxPoints of them.
constexpr float kPointOpacityMin = 0.05f;
constexpr size_t kMaxPoints = 40000;

bool IsFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

void ReadPoints(const fs::path& path, View3dScene* scene, QStringList* loaded) {
  const DensityGrid grid = ReadDensityGrid(path);
  std::vector<std::pair<Eigen::Vector3f, float>> all;
  grid.ForEachActive([&](const Eigen::Vector3i& ijk, float value) {
    if (value >= kPointOpacityMin) {
      all.emplace_back(grid.WorldFromIndex(ijk.cast<double>()).cast<float>(), value);
    }
  });
  const size_t step = std::max<size_t>(1, (all.size() + kMaxPoints - 1) / kMaxPoints);
  for (size_t i = 0; i < all.size(); i += step) {
    scene->points.push_back(all[i].first);
    scene->point_values.push_back(all[i].second);
    scene->bounds.extend(all[i].first.cast<double>());
  }
  *loaded << QString("%1 voxels").arg(all.size());
}

void ReadSkeleton(const fs::path& path, View3dScene* scene, QStringList* loaded) {
  const SkeletonGraph graph = ReadSkeletonJson(path);
  for (const SkeletonNode& node : graph.nodes) {
    scene->bounds.extend(node.position);
    if (node.parent_idx >= 0) {
      scene->skeleton.emplace_back(node.position, graph.nodes[node.parent_idx].position);
    }
  }
  *loaded << QString("skeleton of %1 nodes").arg(graph.nodes.size());
}

}  // namespace

std::shared_ptr<const View3dScene> LoadView3dScene(const Project& project) {
  auto scene = std::make_shared<View3dScene>();
  QStringList loaded, failed;
  const auto read = [&](const char* name, auto&& reader) {
    const fs::path path = project.OutDir() / name;
    if (!IsFile(path)) return;
    try {
      reader(path);
    } catch (const std::exception& error) {
      failed << QString::fromStdString(error.what());
    }
  };
  read("tree.obj", [&](const fs::path& path) {
    scene->mesh = ReadObj(path);
    if (scene->mesh.NumTriangles() == 0) return;
    for (const Eigen::Vector3f& vertex : scene->mesh.vertices) {
      scene->bounds.extend(vertex.cast<double>());
    }
    loaded << "mesh";
  });
  read("density.vdb", [&](const fs::path& path) { ReadPoints(path, scene.get(), &loaded); });
  read("skeleton.json", [&](const fs::path& path) { ReadSkeleton(path, scene.get(), &loaded); });
  scene->status = loaded.isEmpty() ? "nothing reconstructed yet" : "3D: " + loaded.join(", ");
  if (!failed.isEmpty()) scene->status += "; unreadable: " + failed.join("; ");
  return scene;
}

QColor View3dPointColor(float opacity) {
  return QColor(110, 220, 120, static_cast<int>(40 + 120 * std::min(1.0f, opacity)));
}

QColor View3dSkeletonColor() { return QColor(255, 150, 40); }

}  // namespace sylva
