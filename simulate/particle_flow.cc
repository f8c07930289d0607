#include "simulate/particle_flow.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <tuple>
#include <vector>

#include "core/geometry/box.h"
#include "core/util/check.h"
#include "core/util/random.h"
#include "simulate/neighbor_search.h"
#include "simulate/particle_dynamics.h"
#include "simulate/trace_graph.h"
#include "simulate/trace_index.h"

namespace sylva {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Particles per parallel task: enough work to amortise scheduling.
constexpr size_t kParticleGrain = 256;
// RandomEngine stream of the seeding.
constexpr uint64_t kSeedingStream = 1;
// Finished traces are indexed within the density's bounds grown by this many
// voxels (plus the base radius); traces farther out are never joined.
constexpr double kTraceIndexMargin = 8.0;
// A join point this close to an edge's end (voxels) joins at that node.
constexpr double kSameNodeDistance = 1e-6;

template <typename Body>
void ParallelOver(size_t n, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kParticleGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i < range.end(); ++i) body(i);
                    });
}

// The largest value[i]; non-finite values count as +infinity. Exact, so the
// result does not depend on how the range is split.
double ParallelMax(const std::vector<double>& values) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, values.size(), kParticleGrain), 0.0,
      [&](const tbb::blocked_range<size_t>& range, double best) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
          const double v =
              std::isfinite(values[i]) ? values[i] : std::numeric_limits<double>::infinity();
          best = std::max(best, v);
        }
        return best;
      },
      [](double a, double b) { return std::max(a, b); });
}

struct Particle {
  ParticleState state;  // sim frame
  int id = 0;           // seeding index; a survivor keeps its own
  int mass = 1;         // seeded particles carried
  TraceCursor trace;
};

// The frame of the density's voxels, with the lowest active voxel at 0.
SimFrame FrameOf(const DensityGrid& density, Eigen::Vector3i* min_ijk, Eigen::Vector3d* extent) {
  Eigen::Vector3i max_ijk;
  density.ActiveIndexBounds(min_ijk, &max_ijk);
  *extent = (max_ijk - *min_ijk).cast<double>();
  return {density.WorldFromIndex(min_ijk->cast<double>()), density.voxel_size()};
}

// Voxels per block of the seeding's running sums (SeedPositions).
constexpr size_t kSeedBlock = 64;

// `count` positions (sim frame), each uniform inside a voxel drawn with
// probability proportional to its opacity^exponent, listed in the grid's voxel order
// (spatially coherent, so particles close in space are close in memory).
// The opacities are read in that order and summed; the seeds are assigned
// from that list, and only their voxels' coordinates are looked up.
std::vector<Eigen::Vector3d> SeedPositions(const DensityGrid& density,
                                           const Eigen::Vector3i& min_ijk, int count, uint64_t seed,
                                           double exponent) {
  // The draw weights; 0 for a voxel of no opacity (never drawn).
  std::vector<float> weights = density.ActiveValues();
  for (float& weight : weights) {
    if (!(weight > 0)) {
      weight = 0.0f;
    } else if (exponent != 1.0) {
      weight = static_cast<float>(std::pow(weight, exponent));
    }
  }
  // Their running sum, kept before every kSeedBlock-th voxel so that a
  // block's running sums can be made again exactly (the same additions).
  std::vector<double> block_sums;
  block_sums.reserve(weights.size() / kSeedBlock + 1);
  double total = 0.0;
  for (size_t v = 0; v < weights.size(); ++v) {
    if (v % kSeedBlock == 0) block_sums.push_back(total);
    total += weights[v];
  }
  SYLVA_CHECK_INPUT(total > 0, "density") << "every active voxel has zero opacity";
  // Per seed: where it falls in the cumulative opacity, and its offset in
  // its voxel; drawn in seed order, then sorted by the former.
  struct Seed {
    double cumulative;
    Eigen::Vector3d offset;
  };
  RandomEngine random(seed, kSeedingStream);
  std::vector<Seed> seeds(count);
  for (Seed& s : seeds) {
    s.cumulative = random.Uniform() * total;
    const double dx = random.Uniform(-0.5, 0.5), dy = random.Uniform(-0.5, 0.5),
                 dz = random.Uniform(-0.5, 0.5);
    s.offset = Eigen::Vector3d(dx, dy, dz);
  }
  std::stable_sort(seeds.begin(), seeds.end(),
                   [](const Seed& a, const Seed& b) { return a.cumulative < b.cumulative; });
  // Voxel v takes the seeds in [sum of the weights before it, that + its own)
  // (a voxel of weight 0 takes none): the blocks that hold seeds are summed
  // again from their first voxel.
  std::vector<int64_t> places(count);
  size_t next = 0;
  for (size_t block = 0; block < block_sums.size() && next < seeds.size(); ++block) {
    const size_t end = std::min(weights.size(), (block + 1) * kSeedBlock);
    const double block_end = block + 1 < block_sums.size() ? block_sums[block + 1] : total;
    if (!(seeds[next].cumulative < block_end)) continue;
    double cumulative = block_sums[block];
    for (size_t v = block * kSeedBlock; v < end && next < seeds.size(); ++v) {
      cumulative += weights[v];
      for (; next < seeds.size() && seeds[next].cumulative < cumulative; ++next) {
        places[next] = static_cast<int64_t>(v);
      }
    }
  }
  // Rounding may leave a draw at the very end of the sum: the last voxel
  // that can be drawn.
  if (next < seeds.size()) {
    int64_t last = static_cast<int64_t>(weights.size()) - 1;
    while (weights[last] == 0.0f) --last;
    for (; next < seeds.size(); ++next) places[next] = last;
  }
  const std::vector<Eigen::Vector3i> voxels = density.ActiveVoxelsAt(places);
  std::vector<Eigen::Vector3d> positions(count);
  for (int i = 0; i < count; ++i) {
    positions[i] = (voxels[i] - min_ijk).cast<double>() + seeds[i].offset;
  }
  return positions;
}

// One run of the particle flow.
class ParticleFlow {
 public:
  // The density's active voxels span [0, extent] in the sim frame.
  ParticleFlow(const SimFrame& frame, const Eigen::Vector3d& extent,
               const Eigen::Vector3d& base_in_world, const DirectionField& field,
               const ParticleFlowOptions& options, ParticleFlowSummary* summary);

  void Seed(const std::vector<Eigen::Vector3d>& positions_in_sim);
  // Iterates until every particle has stopped or max_iterations.
  void Run(ProgressTask* progress);
  // Joins particles still flowing to the root by a straight edge.
  void FinishUnarrived();
  SkeletonGraph Skeleton(double simplify_tolerance) const {
    return traces_.ToSkeleton(frame_, base_in_world_, simplify_tolerance);
  }
  int NumTraceNodes() const { return traces_.NumNodes(); }
  double step() const { return controller_.step(); }

 private:
  // Ends a particle's trace at `node` (the root, or a node of another
  // trace), by way of a node where it is now.
  void EndAt(Particle* particle, int node);
  // Where the trace through `node` ends for now: the id of the particle
  // still flowing at its end, or TraceGraph::kRootTrace if it reached the
  // root.
  int Destination(int node) const;
  // Whether `particle` may join the edge from `child` to its parent: a
  // finished trace, or a flowing one (not its own) that it moves along, as
  // the options say.
  bool Joinable(int child, const Particle& particle) const;
  void StopArrivedParticles();
  void JoinTraces();
  // Joins a particle to the nearest trace within merge_distance that does
  // not lead to itself (options: finished traces only, or flowing ones
  // too); false if there is none.
  bool JoinTrace(Particle* particle);
  void FindNeighbors();
  void MergeClosePairs();
  void Merge(int a, int b);
  void FreezeNeighbors();
  void Compact();
  void Advance(const ProgressTask& progress);
  void RecordTraces(const std::vector<ParticleState>& next);

  const ParticleFlowOptions& options_;
  ParticleFlowSummary* summary_;
  SimFrame frame_;
  Eigen::Vector3d base_in_world_;
  Eigen::Vector3d base_in_sim_;
  ParticleForces forces_;
  StepController controller_;
  std::unique_ptr<NeighborSearch> search_;
  TraceGraph traces_;
  std::unique_ptr<TraceIndex> index_;  // traces to join; null if none are joined
  // Per trace (= particle id): the particle it leads to, itself while it
  // flows, kRootTrace once it reached the root (a union-find forest).
  std::vector<int> leads_to_;
  double flowing_join_cos_;  // cos(options.flowing_join_angle_deg)
  int iteration_ = 0;

  std::vector<Particle> particles_;  // still flowing, in ascending id
  // Per particle, within one iteration (indexed like particles_).
  std::vector<char> alive_;
  std::vector<Eigen::Vector3d> positions_;  // for the neighbour search
  std::vector<int> neighbor_idx_;
  std::vector<double> neighbor_distance_;
  std::vector<int> merged_into_;  // survivor of an absorbed particle, else itself
  std::vector<FrozenNeighbor> frozen_;
  std::vector<ParticleState> next_;  // trial states of a step
  std::vector<double> errors_;       // their error estimates
  std::vector<char> new_node_;       // per particle: whether it records a trace node
};

ParticleFlow::ParticleFlow(const SimFrame& frame, const Eigen::Vector3d& extent,
                           const Eigen::Vector3d& base_in_world, const DirectionField& field,
                           const ParticleFlowOptions& options, ParticleFlowSummary* summary)
    : options_(options),
      summary_(summary),
      frame_(frame),
      base_in_world_(base_in_world),
      base_in_sim_(frame.SimFromWorld(base_in_world)),
      forces_(options, base_in_sim_, field, frame),
      controller_(options.initial_step, options.min_step, options.max_step,
                  options.error_tolerance),
      search_(MakeNeighborSearch(
          NeighborSearchKindFromName(options.neighbor_search, "ParticleFlow.neighbor_search"))),
      traces_(base_in_sim_),
      flowing_join_cos_(std::cos(options.flowing_join_angle_deg * M_PI / 180)) {
  if ((options.join_finished_traces || options.join_flowing_traces) && options.merge_distance > 0) {
    const double margin = kTraceIndexMargin + options.base_radius;
    index_ = std::make_unique<TraceIndex>(Eigen::Vector3d::Constant(-margin),
                                          extent.array() + margin, options.merge_distance);
  }
}

void ParticleFlow::Seed(const std::vector<Eigen::Vector3d>& positions_in_sim) {
  particles_.resize(positions_in_sim.size());
  leads_to_.resize(positions_in_sim.size());
  for (size_t i = 0; i < positions_in_sim.size(); ++i) {
    Particle& particle = particles_[i];
    particle.id = static_cast<int>(i);
    particle.state.position = positions_in_sim[i];
    particle.trace = traces_.StartTrace(positions_in_sim[i], particle.id);
    leads_to_[i] = particle.id;
  }
}

void ParticleFlow::Run(ProgressTask* progress) {
  for (iteration_ = 0; iteration_ < options_.max_iterations; ++iteration_) {
    const Clock::time_point start_join = Clock::now();
    StopArrivedParticles();
    JoinTraces();
    summary_->seconds_join += SecondsSince(start_join);
    if (particles_.empty()) break;
    const Clock::time_point start_neighbors = Clock::now();
    FindNeighbors();
    alive_.assign(particles_.size(), 1);
    if (iteration_ > 0) MergeClosePairs();
    FreezeNeighbors();
    Compact();
    summary_->seconds_neighbors += SecondsSince(start_neighbors);
    const Clock::time_point start_integrate = Clock::now();
    Advance(*progress);
    summary_->seconds_integrate += SecondsSince(start_integrate);
    ++summary_->iterations;
    progress->Update(static_cast<double>(iteration_ + 1) / options_.max_iterations);
  }
  StopArrivedParticles();
}

void ParticleFlow::EndAt(Particle* particle, int node) {
  if (particle->trace.anchor != particle->state.position) {
    traces_.RecordNode(&particle->trace, particle->state.position, particle->mass);
  }
  traces_.EndTrace(particle->trace, node, particle->mass);
  leads_to_[particle->id] = Destination(node);
  // Only finished traces are joined: index this one if it now is.
  if (index_ != nullptr && !options_.join_flowing_traces &&
      leads_to_[particle->id] == TraceGraph::kRootTrace) {
    index_->AddSubtree(traces_, particle->trace.last_node);
  }
}

int ParticleFlow::Destination(int node) const {
  int trace = traces_.TraceOf(node);
  while (trace != TraceGraph::kRootTrace && leads_to_[trace] != trace) trace = leads_to_[trace];
  return trace;
}

bool ParticleFlow::Joinable(int child, const Particle& particle) const {
  const int destination = Destination(child);
  if (destination == TraceGraph::kRootTrace) return options_.join_finished_traces;
  if (!options_.join_flowing_traces || destination == particle.id) return false;
  // The same path: the particle moves along the edge's direction.
  const Eigen::Vector3d along = traces_.Position(traces_.Parent(child)) - traces_.Position(child);
  const double norms = along.norm() * particle.state.velocity.norm();
  return norms > 0 && along.dot(particle.state.velocity) >= flowing_join_cos_ * norms;
}

void ParticleFlow::StopArrivedParticles() {
  alive_.assign(particles_.size(), 1);
  const double radius2 = options_.base_radius * options_.base_radius;
  for (size_t i = 0; i < particles_.size(); ++i) {
    Particle& particle = particles_[i];
    if ((particle.state.position - base_in_sim_).squaredNorm() >= radius2) continue;
    EndAt(&particle, TraceGraph::kRoot);
    summary_->reached_base += particle.mass;
    alive_[i] = 0;
  }
  frozen_.resize(particles_.size());
  Compact();
}

void ParticleFlow::JoinTraces() {
  if (index_ == nullptr) return;
  if (options_.join_flowing_traces) index_->AddNewEdges(traces_);
  const size_t n = particles_.size();
  // Candidates in parallel; joins in particle order, each seeing the traces
  // joined before it.
  std::vector<char> near(n);
  ParallelOver(n, [&](size_t i) {
    int child;
    Eigen::Vector3d point;
    near[i] = index_->Nearest(
        traces_, particles_[i].state.position,
        [&](int edge) { return Joinable(edge, particles_[i]); }, &child, &point);
  });
  alive_.assign(n, 1);
  for (size_t i = 0; i < n; ++i) {
    if (near[i] && JoinTrace(&particles_[i])) alive_[i] = 0;
  }
  Compact();
}

bool ParticleFlow::JoinTrace(Particle* particle) {
  int child;
  Eigen::Vector3d point;
  if (!index_->Nearest(
          traces_, particle->state.position, [&](int edge) { return Joinable(edge, *particle); },
          &child, &point)) {
    return false;
  }
  // Join at an end of the edge if the point is one, else at a new node.
  int node = child;
  const int parent = traces_.Parent(child);
  if ((point - traces_.Position(parent)).norm() < kSameNodeDistance) {
    node = parent;
  } else if ((point - traces_.Position(child)).norm() >= kSameNodeDistance ||
             traces_.IsTip(child)) {
    node = traces_.SplitEdge(child, point);
    if (!options_.join_flowing_traces) index_->AddEdge(traces_, node);
  }
  EndAt(particle, node);
  if (options_.join_flowing_traces) index_->AddNewEdges(traces_);
  const int destination = leads_to_[particle->id];
  if (destination == TraceGraph::kRootTrace) {
    summary_->reached_base += particle->mass;
    summary_->trace_joins += 1;
  } else {
    // The particle still flowing at the end of that trace carries this one's
    // particles from now on (particles_ is in ascending id).
    const auto carrier =
        std::lower_bound(particles_.begin(), particles_.end(), destination,
                         [](const Particle& p, int wanted) { return p.id < wanted; });
    SYLVA_CHECK(carrier != particles_.end() && carrier->id == destination);
    // As in a merge, momentum is conserved: the carrier's path is the
    // bundle's, not a lone leader's.
    const int mass = carrier->mass + particle->mass;
    carrier->state.velocity =
        (carrier->mass * carrier->state.velocity + particle->mass * particle->state.velocity) /
        mass;
    carrier->mass = mass;
    summary_->flowing_joins += 1;
  }
  return true;
}

void ParticleFlow::FinishUnarrived() {
  for (Particle& particle : particles_) {
    EndAt(&particle, TraceGraph::kRoot);
    summary_->unfinished += particle.mass;
    ++summary_->unfinished_bundles;
  }
  particles_.clear();
}

void ParticleFlow::FindNeighbors() {
  const size_t n = particles_.size();
  positions_.resize(n);
  ParallelOver(n, [&](size_t i) { positions_[i] = particles_[i].state.position; });
  search_->Build(positions_);
  const double radius = std::max(options_.neighbor_radius, options_.merge_distance);
  search_->AllNearestOthers(radius, &neighbor_idx_, &neighbor_distance_);
  summary_->neighbor_queries += static_cast<int64_t>(n);
}

void ParticleFlow::MergeClosePairs() {
  // Candidate pairs (distance, lower index, higher index), in a fixed order.
  std::vector<std::tuple<double, int, int>> pairs;
  for (size_t i = 0; i < particles_.size(); ++i) {
    const int j = neighbor_idx_[i];
    if (j < 0 || !(neighbor_distance_[i] < options_.merge_distance)) continue;
    pairs.emplace_back(neighbor_distance_[i], std::min<int>(i, j), std::max<int>(i, j));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  merged_into_.resize(particles_.size());
  for (size_t i = 0; i < particles_.size(); ++i) merged_into_[i] = static_cast<int>(i);
  std::vector<char> taken(particles_.size(), 0);
  for (const auto& [distance, a, b] : pairs) {
    if (taken[a] || taken[b]) continue;
    taken[a] = taken[b] = 1;
    Merge(a, b);
  }
}

void ParticleFlow::Merge(int a, int b) {
  // The heavier survives; equal masses: the lower index (= the lower id).
  const int survivor_idx = particles_[b].mass > particles_[a].mass ? b : a;
  const int absorbed_idx = survivor_idx == a ? b : a;
  Particle& survivor = particles_[survivor_idx];
  Particle& absorbed = particles_[absorbed_idx];
  const int junction =
      traces_.NodeAtPosition(&survivor.trace, survivor.state.position, survivor.mass);
  traces_.NodeAtPosition(&absorbed.trace, absorbed.state.position, absorbed.mass);
  traces_.EndTrace(absorbed.trace, junction, absorbed.mass);
  leads_to_[absorbed.id] = survivor.id;
  // Momentum is conserved; the survivor stays where it is.
  const int mass = survivor.mass + absorbed.mass;
  survivor.state.velocity =
      (survivor.mass * survivor.state.velocity + absorbed.mass * absorbed.state.velocity) / mass;
  survivor.mass = mass;
  alive_[absorbed_idx] = 0;
  merged_into_[absorbed_idx] = survivor_idx;
  ++summary_->merges;
}

void ParticleFlow::FreezeNeighbors() {
  const size_t n = particles_.size();
  frozen_.assign(n, FrozenNeighbor());
  const bool merged = iteration_ > 0;
  ParallelOver(n, [&](size_t i) {
    int j = neighbor_idx_[i];
    if (j < 0 || !alive_[i]) return;
    if (merged) j = merged_into_[j];  // an absorbed neighbour is now its survivor
    if (j == static_cast<int>(i)) return;
    const double mass_i = particles_[i].mass, mass_j = particles_[j].mass;
    frozen_[i].position = particles_[j].state.position;
    frozen_[i].pull = options_.neighbor_pull * 2 * mass_j / (mass_i + mass_j);
  });
}

void ParticleFlow::Compact() {
  size_t kept = 0;
  for (size_t i = 0; i < particles_.size(); ++i) {
    if (!alive_[i]) continue;
    if (kept != i) {
      particles_[kept] = particles_[i];
      frozen_[kept] = frozen_[i];
    }
    ++kept;
  }
  particles_.resize(kept);
  frozen_.resize(kept);
}

void ParticleFlow::Advance(const ProgressTask& progress) {
  const size_t n = particles_.size();
  std::vector<ParticleState>& next = next_;
  std::vector<double>& errors = errors_;
  next.resize(n);
  errors.resize(n);
  for (;;) {
    const double step = controller_.step();
    ParallelOver(n, [&](size_t i) {
      next[i] = DoubledRk4Step(forces_, frozen_[i], particles_[i].state, step, &errors[i]);
    });
    const double error = ParallelMax(errors);
    if (controller_.Judge(error)) {
      SYLVA_CHECK(std::isfinite(error))
          << "particle flow diverged (non-finite positions; is the direction field finite?)";
      summary_->simulated_time += step;
      summary_->particle_steps += static_cast<int64_t>(n);
      break;
    }
    ++summary_->rejected_steps;
    progress.CheckCancelled();
  }
  RecordTraces(next);
}

void ParticleFlow::RecordTraces(const std::vector<ParticleState>& next) {
  // Which particles record a node, and its index (in particle order).
  const size_t n = particles_.size();
  new_node_.resize(n);
  ParallelOver(n, [&](size_t i) {
    new_node_[i] = TraceGraph::LeavesRun(particles_[i].trace, particles_[i].state.position,
                                         next[i].position, options_.trace_tolerance);
  });
  // In particle order (node numbers do not depend on the threads).
  for (size_t i = 0; i < n; ++i) {
    Particle& particle = particles_[i];
    if (new_node_[i]) traces_.RecordNode(&particle.trace, particle.state.position, particle.mass);
    TraceGraph::StartRunIfNeeded(&particle.trace, next[i].position);
    particle.state = next[i];
  }
}

void CheckInputs(const DensityGrid& density, const Eigen::Vector3d& base_in_world,
                 const ParticleFlowOptions& options) {
  options.Check();
  SYLVA_CHECK_INPUT(!density.IsEmpty(), "density")
      << "the density grid has no active voxels: there is nothing to seed particles in";
  SYLVA_CHECK_INPUT(base_in_world.allFinite(), "base") << "the tree base must be finite";
  const Box3d bounds = density.ActiveWorldBounds();
  const double margin = std::max(options.base_radius, 1.0) * density.voxel_size();
  const Box3d grown(bounds.min().array() - margin, bounds.max().array() + margin);
  SYLVA_CHECK_INPUT(grown.contains(base_in_world), "base")
      << "the tree base (" << base_in_world.transpose() << ") lies outside the density's active "
      << "bounds (" << bounds.min().transpose() << ") - (" << bounds.max().transpose()
      << ") grown by " << margin << " world units";
}

}  // namespace

SkeletonGraph SimulateParticleFlow(const DensityGrid& density, const Eigen::Vector3d& base_in_world,
                                   const DirectionField& field, const ParticleFlowOptions& options,
                                   ProgressReporter* progress, ParticleFlowSummary* summary,
                                   SkeletonGraph* raw_traces) {
  CheckInputs(density, base_in_world, options);
  ParticleFlowSummary local_summary;
  if (summary == nullptr) summary = &local_summary;
  *summary = ParticleFlowSummary();
  summary->neighbor_search = options.neighbor_search;
  const Clock::time_point start = Clock::now();
  ProgressTask task(progress, "simulate: particle flow");
  task.CheckCancelled();

  Eigen::Vector3i min_ijk;
  Eigen::Vector3d extent;
  const SimFrame frame = FrameOf(density, &min_ijk, &extent);
  ParticleFlow flow(frame, extent, base_in_world, field, options, summary);
  flow.Seed(
      SeedPositions(density, min_ijk, options.num_particles, options.seed, options.seed_exponent));
  summary->seeded = options.num_particles;
  summary->seconds_seed = SecondsSince(start);

  flow.Run(&task);
  flow.FinishUnarrived();
  summary->final_step = flow.step();

  const Clock::time_point start_skeleton = Clock::now();
  summary->raw_nodes = flow.NumTraceNodes();
  if (raw_traces != nullptr) *raw_traces = flow.Skeleton(0.0);
  SkeletonGraph skeleton = flow.Skeleton(options.simplify_tolerance);
  SYLVA_CHECK(skeleton.nodes[0].strands == options.num_particles)
      << "mass not conserved: the root carries " << skeleton.nodes[0].strands << " of "
      << options.num_particles << " particles";
  summary->skeleton_nodes = skeleton.NumNodes();
  summary->seconds_skeleton = SecondsSince(start_skeleton);
  summary->seconds_total = SecondsSince(start);
  task.Update(1.0);
  return skeleton;
}

}  // namespace sylva
