// The online fit's speed (Google Benchmark), each figure as a share of a machine limit
// measured in the same run:
//   - BM_StreamRead / BM_Sgemm measure the limits: reading a buffer the size of the largest
//     basis once, and a 1024^3 single-precision matrix product (one core);
//   - BM_Fit{TermMajor,VertexMajor}/N/V: one customer, N components, V garment vertices, with
//     the basis (mean and terms) stored term-major (each contiguous) or vertex-major; counter
//     `of_bandwidth` is the fit's byte rate over the streaming-read rate;
//   - BM_FitPortable/N/V: TermMajor's product without the AVX2 path (core::MultiplyAccumulate),
//     the same bytes: TermMajor's time over this one is what the runtime dispatch buys here;
//   - BM_FitInt16/N/V: the product as ClothingFitter computes it, the terms in 16 bits
//     (core::Int16Columns): TermMajor's time over this one is what the half-size basis buys;
//   - BM_FitBatch64/N/V: 64 customers as one matrix product; `of_sgemm` is its FLOP rate
//     over the SGEMM rate;
//   - BM_FitKernel/N/V/S: the kernel model (N terms, 2N + 1 + 400 training bodies, 32 outputs;
//     S: the kernel's shape, 0 Gaussian, 1 Matern 3/2, which costs a square root per body more);
//   - BM_FitCleanup/N/V/R/M: a fit plus the collision clean-up (ClothingFitter): vertex anchors
//     only, as bases before guards had (R = 0), or with a guard per body vertex under the
//     garment and R rounds of smoothing over a grid garment's edges (the default is
//     clothing::kSmoothingIterations); M = 1: fitted to a mesh given with the weights
//     (FitToBody) instead of the body of the weights; counter `moved` is the share of vertices
//     the clean-up moved (random geometry moves every vertex, the most work a fit can take);
//   - BM_ProjectAvatar/N: a 13,380-vertex avatar projected onto N components;
//   - BM_BuildKernelModel/N/S/T/B: not the fit but the offline build of its model
//     (BuildKernelClothingModel) from N components' axis examples and S sampled bodies, the
//     kernel shapes searched on T threads and on the first B bodies (0: all), then fitted to
//     all: /T=1 over /T=2 is what the second thread buys, /B=0 over /B=300 what searching on
//     300 of the 641 bodies saves (counter `loo_mm`: the leave-one-out error on all of them);
//   - BM_FitStoredBasis/0..4 (--clothing=PATH.fbc): a real garment size, the model alone, with
//     the clean-up, the clean-up without guards, without smoothing, and fitted to a mesh;
//     BM_FitStoredBasis/5 (with --avatar=PATH.obj --weights=PATH.json, the avatar's projection
//     from `fitbase basis project --json`): fitted to that customer's own mesh, counter `deep`
//     the pushes checked against the body under the garment per fit (each such fit refits
//     that region's tree, of `body_triangles` triangles; 0 at the other arguments' training
//     body when none is deep); BM_FitStoredBasis/6 (with --weights): fitted from those weights
//     alone, the deep pushes checked against the body of the weights; BM_LoadStoredBasis/0
//     what a fit server pays to parse that record and build its fitter, /1 of it the basis's
//     conversion to 16 bits.
// Usage: fitbase_fit_bench [--benchmark_filter=...] [--clothing=PATH.fbc]
//        [--weights=PATH.json [--avatar=PATH.obj]]
#include <optional>
#include <random>
#include <string>

#include "benchmark/benchmark.h"
#include "body/body_model.h"
#include "clothing/clothing_fitter.h"
#include "clothing/clothing_model.h"
#include "core/file_util.h"
#include "core/kernel_ridge.h"
#include "core/matrix_vector.h"
#include "core/mesh.h"
#include "core/obj_io.h"
#include "core/pca_basis.h"
#include "fitbase/v1/avatar.pb.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "proto/clothing_basis_codec.h"
#include "proto/json_codec.h"
#include "proto/message_file.h"

namespace fitbase {
namespace {

constexpr int kBodyVertices = static_cast<int>(body::kBodyVertexCount);
constexpr int kBatch = 64;
constexpr int kSgemmSize = 1024;

double g_stream_bytes_per_second = 0;
double g_sgemm_flops_per_second = 0;

// Synthetic linear model (T = N terms): the fit's cost depends on sizes only.
clothing::ClothingModel MakeModel(int components, int vertices) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uniform(-0.01f, 0.01f);
  clothing::ClothingModel model;
  model.component_count = components;
  model.basis =
      Eigen::MatrixXf::NullaryExpr(3 * vertices, components + 1, [&] { return uniform(rng); });
  for (int k = 0; k < components; ++k) {
    model.term_component.push_back(k);
    model.term_power.push_back(1);
  }
  return model;
}

Eigen::VectorXf Weights(int components) {
  return Eigen::VectorXf::LinSpaced(components, -0.02f, 0.03f);
}

double FitBytes(int components, int vertices) {
  return 4.0 * 3 * vertices * (components + 2);  // Mean and terms read, result written.
}

void BM_StreamRead(benchmark::State& state) {
  const Eigen::VectorXf buffer = Eigen::VectorXf::Ones(static_cast<Eigen::Index>(FitBytes(60, 20000) / 4));
  for (auto _ : state) {
    float sum = buffer.sum();
    benchmark::DoNotOptimize(sum);
  }
  const double bytes = 4.0 * static_cast<double>(buffer.size());
  state.counters["bytes_per_second"] =
      benchmark::Counter(bytes * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<int64_t>(bytes) * state.iterations());
}

void BM_Sgemm(benchmark::State& state) {
  const Eigen::MatrixXf a = Eigen::MatrixXf::Random(kSgemmSize, kSgemmSize);
  const Eigen::MatrixXf b = Eigen::MatrixXf::Random(kSgemmSize, kSgemmSize);
  Eigen::MatrixXf c(kSgemmSize, kSgemmSize);
  for (auto _ : state) {
    c.noalias() = a * b;
    benchmark::DoNotOptimize(c.data());
  }
  state.counters["flops"] = benchmark::Counter(
      2.0 * kSgemmSize * kSgemmSize * kSgemmSize * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}

// Google Benchmark reports rates after a run; the limits are taken from the first runs'
// counters by a reporter hook below, so each fit's share is computed against this machine.
void SetShareOfBandwidth(benchmark::State& state, double bytes) {
  if (g_stream_bytes_per_second == 0) return;  // BM_StreamRead filtered out.
  state.counters["of_bandwidth"] = benchmark::Counter(
      bytes * static_cast<double>(state.iterations()) / g_stream_bytes_per_second,
      benchmark::Counter::kIsRate);
}

void BM_FitTermMajor(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), v = static_cast<int>(state.range(1));
  const clothing::ClothingModel model = MakeModel(n, v);
  const Eigen::VectorXf w = Weights(n);
  Eigen::VectorXf features, out;
  for (auto _ : state) {
    clothing::FitClothing(model, w, features, out);
    benchmark::DoNotOptimize(out.data());
  }
  SetShareOfBandwidth(state, FitBytes(n, v));
}

void BM_FitPortable(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), v = static_cast<int>(state.range(1));
  const clothing::ClothingModel model = MakeModel(n, v);
  Eigen::VectorXf features(n + 1);
  features << 1, Weights(n);
  Eigen::VectorXf out(3 * v);
  for (auto _ : state) {
    out.setZero();
    core::MultiplyAccumulatePortable(model.basis, features, out);
    benchmark::DoNotOptimize(out.data());
  }
  SetShareOfBandwidth(state, FitBytes(n, v));
  state.counters["avx2_path"] = core::MultiplyAccumulateUsesAvx2();
}

// The basis as ClothingFitter holds it: the mean in floats, the terms in 16 bits.
void BM_FitInt16(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), v = static_cast<int>(state.range(1));
  const clothing::ClothingModel model = MakeModel(n, v);
  const Eigen::VectorXf mean = model.basis.col(0);
  const core::Int16Columns terms = core::QuantizeColumns(model.basis.rightCols(n));
  const Eigen::VectorXf w = Weights(n);
  Eigen::VectorXf out;
  for (auto _ : state) {
    out = mean;
    core::MultiplyAccumulate(terms, w, out);
    benchmark::DoNotOptimize(out.data());
  }
  SetShareOfBandwidth(state, 4.0 * 3 * v * 2 + static_cast<double>(terms.bytes()));
  state.counters["avx2_path"] = core::MultiplyAccumulateUsesAvx2();
}

void BM_FitVertexMajor(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), v = static_cast<int>(state.range(1));
  const clothing::ClothingModel model = MakeModel(n, v);
  const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> basis = model.basis;
  Eigen::VectorXf features(n + 1);
  features << 1, Weights(n);
  Eigen::VectorXf out;
  for (auto _ : state) {
    out.noalias() = basis * features;
    benchmark::DoNotOptimize(out.data());
  }
  SetShareOfBandwidth(state, FitBytes(n, v));
}

void BM_FitBatch64(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), v = static_cast<int>(state.range(1));
  const clothing::ClothingModel model = MakeModel(n, v);
  const Eigen::MatrixXf weights = Weights(n).replicate(1, kBatch);
  Eigen::MatrixXf out;
  for (auto _ : state) {
    clothing::FitClothingBatch(model, weights, out);
    benchmark::DoNotOptimize(out.data());
  }
  const double flops = 2.0 * 3 * v * n * kBatch;
  if (g_sgemm_flops_per_second > 0) state.counters["of_sgemm"] = benchmark::Counter(
      flops * static_cast<double>(state.iterations()) / g_sgemm_flops_per_second,
      benchmark::Counter::kIsRate);
  state.counters["fits_per_second"] =
      benchmark::Counter(kBatch * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// Drapes that follow the weights non-linearly, each vertex its own mix of every component's
// saturating slide and a bulge, so that the relevance search has reaches to find: D x M.
Eigen::MatrixXd SyntheticDrapes(const Eigen::VectorXd& sigmas, const Eigen::MatrixXd& weights,
                                int vertices) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const Eigen::Index n = sigmas.size();
  const Eigen::MatrixXd slide =
      Eigen::MatrixXd::NullaryExpr(3 * vertices, n, [&] { return 0.01 * normal(rng); });
  const Eigen::MatrixXd bulge =
      Eigen::MatrixXd::NullaryExpr(3 * vertices, n, [&] { return 0.002 * normal(rng); });
  const Eigen::MatrixXd z = sigmas.cwiseInverse().asDiagonal() * weights;
  return slide * z.array().tanh().matrix() + bulge * z.array().square().matrix();
}

void BM_BuildKernelModel(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), sampled = static_cast<int>(state.range(1));
  constexpr int kVertices = 500;
  const Eigen::VectorXd sigmas = Eigen::VectorXd::LinSpaced(n, 2.0, 0.2);
  const clothing::ExampleDesign design = *clothing::MakeExampleDesign(sigmas, 1.0);
  Eigen::MatrixXd axis(n, design.example_count());
  for (int e = 0; e < design.example_count(); ++e) axis.col(e) = design.Weights(e);
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  clothing::SampledDrapes samples;
  samples.weights =
      sigmas.asDiagonal() * Eigen::MatrixXd::NullaryExpr(n, sampled, [&] { return normal(rng); });
  samples.drapes = SyntheticDrapes(sigmas, samples.weights, kVertices);
  const Eigen::MatrixXd axis_drapes = SyntheticDrapes(sigmas, axis, kVertices);
  clothing::KernelBuildReport report;
  const int search = state.range(3) > 0 ? static_cast<int>(state.range(3))
                                        : design.example_count() + sampled;
  for (auto _ : state) {
    absl::StatusOr<clothing::ClothingModel> model = clothing::BuildKernelClothingModel(
        design, axis_drapes, samples,
        {.threads = static_cast<int>(state.range(2)), .search_bodies = search}, &report);
    if (!model.ok()) {
      state.SkipWithError(std::string(model.status().message()).c_str());
      return;
    }
    benchmark::DoNotOptimize(model->basis.data());
  }
  state.SetLabel(report.input_scaling + " " + report.shape);
  state.counters["loo_mm"] = report.loo_rms_mm;
}

// The kernel model at its largest default: N linear terms, M = 2N + 1 + 400 training bodies
// (400 sampled drapes) and C = 32 outputs. Its share of the bandwidth counts the mean, the
// terms and the outputs read once, and the centers and coefficients.
void BM_FitKernel(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), v = static_cast<int>(state.range(1));
  constexpr int kOutputs = 32;
  const int centers = 2 * n + 1 + 400;
  clothing::ClothingModel model = MakeModel(n, v);
  model.method = clothing::ClothingMethod::kKernel;
  model.basis.conservativeResize(Eigen::NoChange, 1 + n + kOutputs);
  model.basis.rightCols(kOutputs).setRandom();
  model.kernel.shape = static_cast<core::KernelShape>(state.range(2));
  model.kernel.length_scale = 3.0f;
  model.kernel.input_scale = Eigen::VectorXf::Constant(n, 50.0f);
  model.kernel.centers = Eigen::MatrixXf::Random(n, centers);
  model.kernel.coefficients = Eigen::MatrixXf::Random(kOutputs, centers) * 0.01f;
  const Eigen::VectorXf w = Weights(n);
  Eigen::VectorXf features, out;
  for (auto _ : state) {
    clothing::FitClothing(model, w, features, out);
    benchmark::DoNotOptimize(out.data());
  }
  SetShareOfBandwidth(state, FitBytes(n + kOutputs, v) + 4.0 * centers * (n + kOutputs));
}

void BM_FitCleanup(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), v = static_cast<int>(state.range(1));
  const int rounds = static_cast<int>(state.range(2));
  std::mt19937 rng(2);
  clothing::BodyCorrespondence c;
  c.offset = 0.0025;
  const int u = std::min(v, kBodyVertices) / 2;
  for (int i = 0; i < u; ++i) c.body_vertices.push_back(2 * i);
  c.body_mean = Eigen::VectorXf::Random(3 * u);
  c.body_components = Eigen::MatrixXf::Random(3 * u, n);
  c.corners.resize(v, 3);
  c.barycentric.resize(v, 3);
  for (int i = 0; i < v; ++i) {
    c.corners.row(i) << static_cast<int32_t>(rng() % u), static_cast<int32_t>(rng() % u),
        static_cast<int32_t>(rng() % u);
    c.barycentric.row(i) << 0.2f, 0.3f, 0.5f;
  }
  if (rounds > 0) {
    // The garment as a grid of triangles, 100 vertices a row; one guard per body vertex, on
    // the grid's triangles in turn.
    const int columns = 100;
    core::Triangles grid(2 * (v / columns - 1) * (columns - 1), 3);
    Eigen::Index t = 0;
    for (int row = 0; row + 1 < v / columns; ++row) {
      for (int col = 0; col + 1 < columns; ++col) {
        const int a = row * columns + col;
        grid.row(t++) << a, a + 1, a + columns;
        grid.row(t++) << a + 1, a + columns + 1, a + columns;
      }
    }
    c.guard_triangles.resize(u, 3);
    for (int i = 0; i < u; ++i) {
      c.guard_body.push_back(i);
      c.guard_triangles.row(i) = grid.row(i % grid.rows());
    }
    c.smoothing_iterations = rounds;
    if (!clothing::SetGarmentNeighbors(grid, c).ok()) state.SkipWithError("bad grid");
  }
  const clothing::ClothingFitter fitter = *clothing::ClothingFitter::Create(MakeModel(n, v), c);
  const Eigen::VectorXf w = Weights(n);
  clothing::FitScratch scratch;
  Eigen::VectorXf out;
  int64_t moved = 0;
  if (state.range(3) == 0) {
    for (auto _ : state) {
      moved = *fitter.Fit(w, true, scratch, out);
      benchmark::DoNotOptimize(out.data());
    }
  } else {
    // Fitted to a mesh given with the weights (FitToBody): the body of the weights 1 mm higher.
    Eigen::VectorXf points;
    clothing::BodyPointsOfWeights(c, w, points);
    std::vector<float> mesh(3 * static_cast<size_t>(kBodyVertices), 0.0f);
    for (int i = 0; i < u; ++i) {
      for (int k = 0; k < 3; ++k) {
        mesh[3 * static_cast<size_t>(c.body_vertices[i]) + k] =
            points(3 * i + k) + (k == 1 ? 0.001f : 0.0f);
      }
    }
    for (auto _ : state) {
      moved = *fitter.FitToBody(w, mesh, true, scratch, out);
      benchmark::DoNotOptimize(out.data());
    }
  }
  state.counters["moved"] = static_cast<double>(moved) / v;
}

// --clothing=PATH: a stored clothing basis (.fbc), fitted at the weights of its last training
// body (a sampled body for kernel), so the clean-up meets a real garment on a real body.
std::string g_clothing_path;
std::string g_avatar_path;
std::string g_weights_path;

// --weights as floats, if it has the basis's count.
std::optional<Eigen::VectorXf> ReadWeights(int components) {
  absl::StatusOr<std::string> json = core::ReadFileToString(g_weights_path);
  v1::AvatarWeights weights;
  if (!json.ok() || !proto::ParseJson(*json, &weights).ok() ||
      weights.weights_size() != components) {
    return std::nullopt;
  }
  return Eigen::Map<const Eigen::VectorXd>(weights.weights().data(), weights.weights_size())
      .cast<float>();
}

// Arg 0: the model alone; 1: with the clean-up; 2: the clean-up without its triangle guards;
// 3: the clean-up without smoothing; 4: with the clean-up, fitted to a mesh given with the
// weights (FitToBody), here the body of the weights 1 mm higher; 5: fitted to --avatar's mesh
// at --weights; 6: fitted from --weights alone.
void BM_FitStoredBasis(benchmark::State& state) {
  v1::ClothingBasis message;
  if (!proto::ReadMessageFile(g_clothing_path, &message).ok()) {
    state.SkipWithError("cannot read --clothing");
    return;
  }
  absl::StatusOr<clothing::ClothingModel> model = proto::ClothingModelFromProto(message);
  absl::StatusOr<clothing::BodyCorrespondence> loaded = proto::BodyCorrespondenceFromProto(message);
  if (!model.ok() || !loaded.ok() || message.provenance().examples().empty()) {
    state.SkipWithError("not a usable clothing basis");
    return;
  }
  clothing::BodyCorrespondence correspondence = *std::move(loaded);
  if (state.range(0) == 2) {
    correspondence.guard_body.clear();
    correspondence.guard_triangles.resize(0, 3);
  } else if (state.range(0) == 3) {
    correspondence.smoothing_iterations = 0;
  }
  const clothing::ClothingFitter fitter =
      *clothing::ClothingFitter::Create(*std::move(model), std::move(correspondence));
  const auto& example = *message.provenance().examples().rbegin();
  const Eigen::VectorXf w =
      Eigen::Map<const Eigen::VectorXd>(example.weights().data(), example.weights_size())
          .cast<float>();
  clothing::FitScratch scratch;
  Eigen::VectorXf out;
  if (state.range(0) >= 5) {
    const std::optional<Eigen::VectorXf> own_weights = ReadWeights(fitter.component_count());
    absl::StatusOr<core::Mesh> avatar =
        state.range(0) == 5 ? core::ReadObj(g_avatar_path) : core::Mesh();
    if (!avatar.ok() || !own_weights) {
      state.SkipWithError("cannot read --avatar or --weights for this basis");
      return;
    }
    const std::vector<float> mesh = core::InterleavedFloats(avatar->positions);
    for (auto _ : state) {
      benchmark::DoNotOptimize(state.range(0) == 5
                                   ? fitter.FitToBody(*own_weights, mesh, true, scratch, out)
                                   : fitter.Fit(*own_weights, true, scratch, out));
    }
  } else if (state.range(0) == 4) {
    const clothing::BodyCorrespondence& c = fitter.correspondence();
    Eigen::VectorXf points;
    clothing::BodyPointsOfWeights(c, w, points);
    std::vector<float> mesh(3 * static_cast<size_t>(kBodyVertices), 0.0f);
    for (size_t i = 0; i < c.body_vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        mesh[3 * static_cast<size_t>(c.body_vertices[i]) + k] =
            points(3 * static_cast<Eigen::Index>(i) + k) + (k == 1 ? 0.001f : 0.0f);
      }
    }
    for (auto _ : state) {
      benchmark::DoNotOptimize(fitter.FitToBody(w, mesh, true, scratch, out));
    }
  } else {
    for (auto _ : state) {
      benchmark::DoNotOptimize(fitter.Fit(w, state.range(0) > 0, scratch, out));
    }
  }
  state.counters["deep"] = static_cast<double>(scratch.cleanup.deep_checks);
  state.counters["vertices"] = static_cast<double>(message.vertex_count());
  state.counters["guards"] = static_cast<double>(fitter.correspondence().guard_body.size());
  state.counters["body_points"] =
      static_cast<double>(fitter.correspondence().body_vertices.size());
  state.counters["body_triangles"] =
      static_cast<double>(fitter.correspondence().body_triangles.rows());
  state.counters["anchors"] = static_cast<double>(fitter.correspondence().anchors_per_vertex);
  // What the fitter holds in all, and its basis in 16 bits against the floats it was stored in.
  const auto columns = static_cast<double>(message.terms_size() + message.kernel().outputs_size());
  state.counters["held_MB"] = static_cast<double>(fitter.bytes()) / 1e6;
  state.counters["basis_MB"] = 1e-6 * (4.0 * message.mean_size() + 2.0 * columns);
  state.counters["basis_float_MB"] = 4e-6 * (message.mean_size() + columns);
}

// What a fit server pays on a cache miss, after reading the record: parsing it, building the
// fitter (validation, and its basis put into 16 bits), and that conversion alone.
void BM_LoadStoredBasis(benchmark::State& state) {
  std::string bytes;
  v1::ClothingBasis message;
  if (!proto::ReadMessageFile(g_clothing_path, &message).ok() ||
      !message.SerializeToString(&bytes)) {
    state.SkipWithError("cannot read --clothing");
    return;
  }
  const absl::StatusOr<clothing::ClothingModel> model = proto::ClothingModelFromProto(message);
  if (!model.ok()) {
    state.SkipWithError("not a usable clothing basis");
    return;
  }
  for (auto _ : state) {
    if (state.range(0) == 0) {
      v1::ClothingBasis parsed;
      benchmark::DoNotOptimize(parsed.ParseFromString(bytes));
      benchmark::DoNotOptimize(proto::ClothingFitterFromProto(parsed));
    } else {
      benchmark::DoNotOptimize(
          core::QuantizeColumns(model->basis.rightCols(model->basis.cols() - 1)));
    }
  }
}

void BM_ProjectAvatar(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  core::PcaBasis basis;
  basis.mean = Eigen::VectorXd::Zero(3 * kBodyVertices);
  basis.components = Eigen::MatrixXd::Random(3 * kBodyVertices, n);
  const Eigen::VectorXd avatar = Eigen::VectorXd::Random(3 * kBodyVertices);
  for (auto _ : state) {
    Eigen::VectorXd w = core::ProjectOntoBasis(basis, avatar);
    benchmark::DoNotOptimize(w.data());
  }
  SetShareOfBandwidth(state, 8.0 * 3 * kBodyVertices * (n + 2));
}

void FitSizes(benchmark::internal::Benchmark* b) {
  for (int n : {10, 30, 60}) {
    for (int v : {2000, 8000, 20000}) b->Args({n, v});
  }
}

// Captures the limits as soon as their benchmarks finish, before any fit runs.
class LimitCapture : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_name.function_name == "BM_StreamRead") {
        g_stream_bytes_per_second = run.counters.at("bytes_per_second");
      } else if (run.run_name.function_name == "BM_Sgemm") {
        g_sgemm_flops_per_second = run.counters.at("flops");
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

BENCHMARK(BM_StreamRead);
BENCHMARK(BM_Sgemm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitTermMajor)->Apply(FitSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FitPortable)->Apply(FitSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FitInt16)->Apply(FitSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FitVertexMajor)->Apply(FitSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FitBatch64)->Apply(FitSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FitKernel)
    ->Args({20, 2000, 1})
    ->Args({20, 8000, 0})
    ->Args({20, 8000, 1})
    ->Args({30, 8000, 1})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FitCleanup)
    ->Args({30, 2000, 0, 0})
    ->Args({30, 2000, clothing::kSmoothingIterations, 0})
    ->Args({30, 8000, 0, 0})
    ->Args({30, 8000, clothing::kSmoothingIterations, 0})
    ->Args({30, 8000, clothing::kSmoothingIterations, 1})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ProjectAvatar)->Arg(10)->Arg(30)->Arg(60)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BuildKernelModel)
    ->Args({20, 300, 1, 0})
    ->Args({20, 300, 2, 0})
    ->Args({20, 600, 2, 0})
    ->Args({20, 600, 2, 300})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace fitbase

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--clothing=", 0) == 0) fitbase::g_clothing_path = arg.substr(11);
    if (arg.rfind("--avatar=", 0) == 0) fitbase::g_avatar_path = arg.substr(9);
    if (arg.rfind("--weights=", 0) == 0) fitbase::g_weights_path = arg.substr(10);
  }
  if (!fitbase::g_clothing_path.empty()) {
    const bool weights = !fitbase::g_weights_path.empty();
    auto* stored = benchmark::RegisterBenchmark("BM_FitStoredBasis", fitbase::BM_FitStoredBasis)
                       ->DenseRange(0, 4)
                       ->Unit(benchmark::kMicrosecond);
    if (weights && !fitbase::g_avatar_path.empty()) stored->Arg(5);
    if (weights) stored->Arg(6);
    benchmark::RegisterBenchmark("BM_LoadStoredBasis", fitbase::BM_LoadStoredBasis)
        ->DenseRange(0, 1)
        ->Unit(benchmark::kMillisecond);
  }
  fitbase::LimitCapture reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
