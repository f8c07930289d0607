// A laser-scanned tree's QSM table as a photo set with a known skeleton: the
// bark `sylva mesh-qsm` makes of the table, rendered from the synthetic
// views; the table's largest part (by length) is the true skeleton. Used by
// the skeleton fidelity test and tests/bench/skeleton_probe.cc.
#ifndef SYLVA_TESTS_FIDELITY_QSM_PHOTOS_H_
#define SYLVA_TESTS_FIDELITY_QSM_PHOTOS_H_

#include <string>
#include <utility>

#include "core/io/qsm_io.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "ui/pipeline/qsm_meshing.h"

namespace sylva {

inline SyntheticDataset QsmPhotoDataset(const std::string& path,
                                        const SyntheticDatasetOptions& views,
                                        const PipelineOptions& options) {
  const double merge_fraction = 0.1;  // mesh-qsm's default --merge
  const QsmMeshing meshing = MeshQsm(ReadQsmCsv(path), options, merge_fraction);
  SyntheticTree tree;
  tree.mesh = meshing.bark;
  for (const QsmSkeleton& part : meshing.parts) {
    if (part.skeleton.TotalLength() > tree.skeleton.TotalLength()) tree.skeleton = part.skeleton;
  }
  return RenderSyntheticDataset(std::move(tree), views);
}

}  // namespace sylva

#endif  // SYLVA_TESTS_FIDELITY_QSM_PHOTOS_H_
