// Livewire attractor graphs of a synthetic dataset's input views, as the
// attract stage traces them with Attractors.mode=auto (General.seed's
// livewire stream, paths to the tree base estimated from the density), for
// tests and probes that build skeletons in memory.
#ifndef SYLVA_TESTS_FIDELITY_SYNTHETIC_LIVEWIRE_H_
#define SYLVA_TESTS_FIDELITY_SYNTHETIC_LIVEWIRE_H_

#include <vector>

#include "core/util/check.h"
#include "core/util/random.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/attractors/livewire.h"
#include "simulate/particle_flow.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {

// `inputs` and `mattes` are data.InputImageSet() and data.InputMattes(); the
// input views come first in data.photos.
inline std::vector<AttractorGraph2D> SyntheticLivewireGraphs(const SyntheticDataset& data,
                                                             const ImageSet& inputs,
                                                             const std::vector<FloatImage>& mattes,
                                                             const DensityGrid& density,
                                                             const PipelineOptions& options) {
  const Eigen::Vector3d base = EstimateTreeBase(density, options.tree_base);
  LivewireOptions livewire = options.attract.livewire;
  livewire.seed = DeriveSeed(options.general.seed, 3);  // the attract stage's stream
  std::vector<AttractorGraph2D> graphs;
  for (int v = 0; v < inputs.NumViews(); ++v) {
    Eigen::Vector2d target;
    SYLVA_CHECK(inputs.Project(v, base, &target)) << "the tree base is behind view " << v;
    graphs.push_back(TraceAttractorGraph(data.photos[v], mattes[v], target, {}, livewire));
  }
  return graphs;
}

}  // namespace sylva

#endif  // SYLVA_TESTS_FIDELITY_SYNTHETIC_LIVEWIRE_H_
