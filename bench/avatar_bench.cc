// A CLI report of the avatar half's speed, each figure against a baseline or a machine limit
// measured in the same run:
//   - building a body from the sparse targets, against the dense sum a naive model would do,
//     and against streaming the offsets it reads once (the memory floor);
//   - PCA over a population, and projecting one avatar, against streaming the basis once.
// Usage: fitbase_avatar_bench [DATA_DIR] [POPULATION_SIZE]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "benchmark/benchmark.h"
#include "body/body_model.h"
#include "body/macro_weights.h"
#include "body/population_sampler.h"
#include "body/target_file.h"
#include "core/pca_basis.h"

namespace fitbase {
namespace {

using Clock = std::chrono::steady_clock;

// Median seconds per call of `fn` over `reps` calls (after one warm-up call).
template <typename Fn>
double MedianSeconds(int reps, Fn fn) {
  fn();
  std::vector<double> times;
  for (int i = 0; i < reps; ++i) {
    const auto start = Clock::now();
    fn();
    times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::nth_element(times.begin(), times.begin() + reps / 2, times.end());
  return times[reps / 2];
}

int Main(int argc, char** argv) {
  const std::filesystem::path data = argc > 1 ? argv[1] : "data/makehuman";
  const int population = argc > 2 ? std::atoi(argv[2]) : 200;
  if (population < 2) {
    std::fprintf(stderr, "population size must be at least 2\n");
    return 2;
  }

  const auto load_start = Clock::now();
  auto model = body::BodyModel::Load(data);
  const double load_s = std::chrono::duration<double>(Clock::now() - load_start).count();
  if (!model.ok()) {
    std::fprintf(stderr, "%s\n", std::string(model.status().message()).c_str());
    return 1;
  }
  std::printf("body model load (base.obj + 430 targets): %.1f ms\n", 1e3 * load_s);

  const body::BodyParams params = body::SampleBodyParams(body::PopulationPreset::kAllWide, 1, 0);
  const double sparse_s = MedianSeconds(50, [&] { (void)model->BuildFullMesh(params); });

  // Baseline: the same weighted sum with every target stored densely (19,158 x 3 each).
  std::vector<std::pair<core::Positions, double>> dense;
  for (const body::TargetWeight& tw : body::ComputeTargetWeights(params)) {
    auto target = body::ReadTargetFile(data / "targets" / tw.path, body::kFullVertexCount);
    core::Positions full = core::Positions::Zero(body::kFullVertexCount, 3);
    for (size_t i = 0; i < target->indices.size(); ++i) {
      full.row(target->indices[i]) = target->offsets.row(static_cast<Eigen::Index>(i)).cast<double>();
    }
    dense.emplace_back(std::move(full), tw.weight);
  }
  core::Positions sum(body::kFullVertexCount, 3);
  const double dense_s = MedianSeconds(50, [&] {
    sum.setZero();
    for (const auto& [offsets, weight] : dense) sum += weight * offsets;
  });
  // The memory floor: streaming once the bytes the sparse build reads (indices and offsets).
  size_t touched_bytes = 0;
  for (const body::TargetWeight& tw : body::ComputeTargetWeights(params)) {
    auto target = body::ReadTargetFile(data / "targets" / tw.path, body::kFullVertexCount);
    touched_bytes += target->indices.size() * (sizeof(int32_t) + 3 * sizeof(float));
  }
  const Eigen::VectorXd stream = Eigen::VectorXd::Random(static_cast<Eigen::Index>(touched_bytes / 8));
  const double floor_s = MedianSeconds(50, [&] {
    double total = stream.sum();
    benchmark::DoNotOptimize(total);
  });
  std::printf("build one full mesh (%zu weighted targets, %.1f MB of offsets): sparse %.0f us, "
              "dense baseline %.0f us (%.2fx), streaming the offsets once %.0f us (build at %.0f%% "
              "of memory bandwidth)\n",
              dense.size(), 1e-6 * static_cast<double>(touched_bytes), 1e6 * sparse_s,
              1e6 * dense_s, dense_s / sparse_s, 1e6 * floor_s, 100 * floor_s / sparse_s);

  Eigen::MatrixXd samples(3 * body::kBodyVertexCount, population);
  for (int i = 0; i < population; ++i) {
    auto body = model->BuildBody(body::SampleBodyParams(body::PopulationPreset::kAllWide, 1, i));
    samples.col(i) = Eigen::Map<const Eigen::VectorXd>(body->positions.data(), body->positions.size());
  }
  const auto pca_start = Clock::now();
  auto basis = core::BuildPcaBasis(samples, core::ComponentSelection{});
  const double pca_s = std::chrono::duration<double>(Clock::now() - pca_start).count();
  const Eigen::Index n = basis->components.cols();
  std::printf("PCA of %d avatars (D = %ld): %.2f s, %ld components for 1 mm\n", population,
              static_cast<long>(samples.rows()), pca_s, static_cast<long>(n));

  const Eigen::VectorXd avatar = samples.col(0);
  Eigen::VectorXd weights;
  const double project_s =
      MedianSeconds(200, [&] { weights = core::ProjectOntoBasis(*basis, avatar); });
  const double stream_s = MedianSeconds(200, [&] {
    double sum = basis->components.sum();
    benchmark::DoNotOptimize(sum);
  });
  std::printf("project one avatar: %.0f us; streaming the %.1f MB basis once: %.0f us "
              "(projection at %.0f%% of the bandwidth limit)\n",
              1e6 * project_s, 8e-6 * static_cast<double>(basis->components.size()),
              1e6 * stream_s, 100 * stream_s / project_s);
  return 0;
}

}  // namespace
}  // namespace fitbase

int main(int argc, char** argv) { return fitbase::Main(argc, argv); }
