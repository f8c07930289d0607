// Compares a folder of mattes with a folder of ground-truth silhouettes: the
// IoU, precision and recall of every matte thresholded at 0.5, and their
// median and minimum. The by-hand check behind the matte-set defaults
// (e.g. sylva's out/mattes/ of the Phenomenal cabin photos against upstream's
// silhouettes).
//
//   sylva_matte_folder_probe MATTES_DIR TRUTH_DIR [DIFF_DIR]
//
// With DIFF_DIR, writes a picture per matte there: white where both are
// foreground, red where only the matte is (false foreground), blue where only
// the truth is (missed).
//
// Every image under TRUTH_DIR is compared with the matte of the same relative
// name (any image extension) under MATTES_DIR; truth images with several
// channels are read by their first channel (Phenomenal's grey + alpha files).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "datasets/eval/silhouette_metrics.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

FloatImage DiffPicture(const FloatImage& matte, const FloatImage& truth) {
  FloatImage picture(matte.width(), matte.height(), 3);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      const bool m = matte.at(x, y) >= 0.5f, t = truth.at(x, y) >= 0.5f;
      picture.at(x, y, 0) = m ? 1.0f : 0.0f;
      picture.at(x, y, 1) = m && t ? 1.0f : 0.0f;
      picture.at(x, y, 2) = t ? 1.0f : 0.0f;
    }
  }
  return picture;
}

int Run(int argc, char** argv) {
  SYLVA_CHECK_INPUT(argc == 3 || argc == 4, "arguments")
      << "usage: sylva_matte_folder_probe MATTES_DIR TRUTH_DIR [DIFF_DIR]";
  const fs::path mattes_dir = argv[1], truth_dir = argv[2];
  const fs::path diff_dir = argc == 4 ? fs::path(argv[3]) : fs::path();
  std::vector<double> ious;
  for (const std::string& name : ListImageFiles(truth_dir)) {
    const fs::path matte_path = FindMatteFile(mattes_dir, name);
    if (matte_path.empty()) {
      std::printf("%-28s no matte\n", name.c_str());
      continue;
    }
    const FloatImage truth = ReadImage(truth_dir / name).Channel(0);
    const FloatImage matte = ReadMatte(matte_path);
    const SilhouetteScores s = CompareSilhouettes(matte, truth);
    std::printf("%-28s IoU %.4f precision %.4f recall %.4f\n", name.c_str(), s.iou, s.precision,
                s.recall);
    ious.push_back(s.iou);
    if (!diff_dir.empty()) {
      const fs::path out = diff_dir / fs::path(name).replace_extension(".png");
      fs::create_directories(out.parent_path());
      WriteImage(out, DiffPicture(matte, truth));
    }
  }
  SYLVA_CHECK_INPUT(!ious.empty(), truth_dir.string()) << "no matte matched a truth image";
  std::sort(ious.begin(), ious.end());
  const size_t n = ious.size();
  const double median = n % 2 ? ious[n / 2] : 0.5 * (ious[n / 2 - 1] + ious[n / 2]);
  std::printf("%zu mattes: IoU median %.4f, min %.4f\n", n, median, ious.front());
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  return sylva::GuardedMain([&] { return sylva::Run(argc, argv); });
}
