// Writes a synthetic dataset (see synthetic_dataset.h) and prints how long
// generation, rendering and writing took.
//
//   make_synthetic_dataset OUT_DIR [--seed N] [--views K] [--held-out H]
//       [--camera pinhole|orthographic] [--size PX] [--samples S]
//       [--elevation DEG] [--distortion K]
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>

#include "core/util/check.h"
#include "datasets/synthetic/synthetic_dataset.h"

namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

sylva::SyntheticDatasetOptions ParseArgs(int argc, char** argv) {
  sylva::SyntheticDatasetOptions options;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const std::string value = argv[i + 1];
    if (flag == "--seed") {
      options.seed = std::stoull(value);
    } else if (flag == "--views") {
      options.num_views = std::stoi(value);
    } else if (flag == "--held-out") {
      options.num_held_out = std::stoi(value);
    } else if (flag == "--camera") {
      SYLVA_CHECK_INPUT(value == "pinhole" || value == "orthographic", flag)
          << "expected pinhole or orthographic";
      options.camera = value == "pinhole" ? sylva::SyntheticCameraKind::kPinhole
                                          : sylva::SyntheticCameraKind::kOrthographic;
    } else if (flag == "--size") {
      options.image_size = std::stoi(value);
    } else if (flag == "--samples") {
      options.samples_per_axis = std::stoi(value);
    } else if (flag == "--elevation") {
      options.elevation_deg = std::stod(value);
    } else if (flag == "--distortion") {
      options.radial_distortion = std::stod(value);
    } else {
      SYLVA_INPUT_ERROR(flag) << "unknown option";
    }
  }
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || (argc % 2) != 0) {
    std::cerr << "usage: make_synthetic_dataset OUT_DIR [--seed N] [--views K] [--held-out H] "
                 "[--camera pinhole|orthographic] [--size PX] [--samples S] [--elevation DEG] "
                 "[--distortion K]\n";
    return 2;
  }
  try {
    const sylva::SyntheticDatasetOptions options = ParseArgs(argc, argv);
    Clock::time_point start = Clock::now();
    const sylva::SyntheticTree tree = sylva::GenerateSyntheticTree(options.tree, options.seed);
    std::cout << "tree: " << SecondsSince(start) << " s, " << tree.skeleton.NumNodes() << " nodes, "
              << tree.num_clusters << " clusters, " << tree.num_leaves << " leaves, "
              << tree.mesh.NumTriangles() << " triangles\n";
    const sylva::Box3d bounds = tree.mesh.Bounds();
    std::cout << "bounds: x [" << bounds.min().x() << ", " << bounds.max().x() << "], y ["
              << bounds.min().y() << ", " << bounds.max().y() << "], z [" << bounds.min().z()
              << ", " << bounds.max().z() << "] m\n";
    start = Clock::now();
    const sylva::SyntheticDataset dataset = sylva::MakeSyntheticDataset(options);
    std::cout << "dataset (tree + cameras + " << dataset.image_set.NumViews()
              << " renders): " << SecondsSince(start) << " s\n";
    start = Clock::now();
    sylva::WriteSyntheticDataset(dataset, options, argv[1]);
    std::cout << "write: " << SecondsSince(start) << " s\n";
  } catch (const sylva::Error& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
