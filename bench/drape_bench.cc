// The offline fitter's figures over the shared garments:
//   fitbase_drape_bench --basis B.fbb [--garments a,b|all] [--sizes S,M,XL] [--jobs 2]
//                       [--smoothness | --smoothness-only] [--smoothness-at C:S,...]
//                       [--smoothness-around DIR] [--smoothness-size M]
//                       [--homotopy-steps P] [--out DIR] [--rows R.csv]
// Drapes every garment in every size onto ten bodies (women and men: average, heavy, thin,
// tall, short) and prints, per garment, seconds per drape (each drape single-threaded; --jobs
// runs drapes side by side), penetration, strain (flagged drapes counted apart) and ease.
// --smoothness adds (--smoothness-only prints alone), for each garment on the average body of
// its wearers, the second difference
// |D(b + d) + D(b - d) - 2 D(b)| for d = 0.1 sigma along the first component (per vertex, its
// largest coordinate: the worst vertex, the 99th percentile and the share over 1 mm), and how
// far doubling the iteration budget moves the result, and the second difference at d / 2 with
// how the vertices over 1 mm scale (steady, like kinks, or smooth). --smoothness-at takes it
// around other bodies too: the average body moved S sigma along component C, for each C:S,
// with each garment's worst over them. --smoothness-around takes it around every avatar of a
// population folder instead of the average body (each moved by the points, so 0:0 is the
// avatar's own mesh), with each drape's stretch and whether it is flagged too small, and the
// median p99 of the flagged and of the others. --smoothness-size is the size it drapes (M, or
// another of --sizes: a loose XL folds where an M lies on the skin).
// --supports drapes each garment (in --sizes) onto its wearers' mean avatar, their five bench
// bodies and the extremes of the calibrated population (the tallest, shortest and heaviest
// --extremes of 500 sampled avatars), and prints where the waistband, collar and leg hems sit
// by the body's landmarks against their place on the mean avatar (over all drapes, and over
// those not flagged too small), with a hem table.
// --speed drapes each garment in size M on its wearers' average body with Eigen's simplicial
// LDL^T and CHOLMOD's supernodal LL^T, then with every step of the path solved to the
// tolerance (the solver before the path's iterations were capped), one after the other in one
// run, with the ratios, how far apart the results are, and whether a repeat of the default
// drape is bitwise equal.
// --homotopy-steps takes every drape of every mode along a path of that many steps from the
// mean avatar (twice as many for the doubled budget): docs/drape.md, "A shorter path, tried,
// not kept".
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <mutex>
#include <optional>
#include <thread>

#include "CLI/CLI.hpp"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_replace.h"
#include "absl/strings/str_split.h"
#include "body/body_measurements.h"
#include "body/body_model.h"
#include "body/population_calibration.h"
#include "core/triangle_bvh.h"
#include "pipeline/garment_importer.h"
#include "pipeline/population_folder.h"
#include "pipeline/progress_reporter.h"
#include "pipeline/skin_visibility.h"
#include "proto/avatar_basis_codec.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"
#include "proto/message_file.h"
#include "workers/cloth_model.h"
#include "workers/fit_metrics.h"
#include "workers/garment_drape.h"

namespace fitbase {
namespace {

struct Body {
  std::string name;
  core::Positions positions;
};

std::vector<Body> TestBodies(const body::BodyModel& model) {
  struct Spec {
    const char* name;
    double gender, weight, height, muscle;
  };
  const Spec specs[] = {
      {"woman", 0.05, 0.5, 0.5, 0.5},        {"woman-heavy", 0.05, 0.9, 0.5, 0.5},
      {"woman-thin", 0.05, 0.15, 0.5, 0.4},  {"woman-tall", 0.05, 0.5, 0.85, 0.5},
      {"woman-short", 0.05, 0.5, 0.15, 0.5}, {"man", 0.95, 0.5, 0.5, 0.5},
      {"man-heavy", 0.95, 0.9, 0.5, 0.6},    {"man-thin", 0.95, 0.15, 0.5, 0.4},
      {"man-tall", 0.95, 0.5, 0.85, 0.5},    {"man-short", 0.95, 0.5, 0.15, 0.5},
  };
  std::vector<Body> bodies;
  for (const Spec& s : specs) {
    body::BodyParams p;
    p.gender = s.gender;
    p.weight = s.weight;
    p.height = s.height;
    p.muscle = s.muscle;
    p.age_years = 35;
    bodies.push_back({s.name, model.BuildBody(p)->positions});
  }
  return bodies;
}

// Runs work(0) .. work(count - 1) on `jobs` threads.
void ForEachSideBySide(size_t count, int jobs, const std::function<void(size_t)>& work) {
  std::atomic<size_t> next{0};
  std::vector<std::thread> threads;
  for (int j = 0; j < jobs; ++j) {
    threads.emplace_back([&] {
      for (size_t i = next++; i < count; i = next++) work(i);
    });
  }
  for (auto& t : threads) t.join();
}

// One drape of the population table, by index into the garments, bodies and sizes.
struct DrapeTask {
  size_t garment, body, size;
};

// One CSV row per drape, for a look at the drapes behind a garment's worst figures.
void WriteRows(const std::string& path, const std::vector<v1::Garment>& imported,
               const std::vector<Body>& bodies, const std::vector<std::string>& size_list,
               const std::vector<DrapeTask>& tasks, const std::vector<v1::DrapeReport>& reports) {
  std::ofstream rows(path);
  rows << "garment,body,size,seconds,penetration_below_0mm,penetration_below_1mm,strain_mean,"
          "strain_p99,strain_max,stretch_p99,compression_p99,overstretched,ease_mean_mm,"
          "converged_max_move_mm,error\n";
  for (size_t i = 0; i < tasks.size(); ++i) {
    const auto [g, b, s] = tasks[i];
    const v1::DrapeReport& r = reports[i];
    // A failed drape's report carries its error as the method.
    const std::string error =
        r.vertex_count() == 0 ? absl::StrReplaceAll(r.method(), {{"\"", "\"\""}}) : "";
    rows << absl::StrFormat(
        "%s,%s,%s,%.3f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%d,%.2f,%.4f,\"%s\"\n",
        imported[g].name(), bodies[b].name, size_list[s], r.seconds(), r.penetration_below_0mm(),
        r.penetration_below_1mm(), r.strain_mean(), r.strain_p99(), r.strain_max(), r.stretch_p99(),
        r.compression_p99(), r.overstretched(), r.ease_mean_mm(), r.converged_max_move_mm(), error);
  }
  if (!rows) std::cerr << "could not write " << path << "\n";
}

// Every garment in every size on every body, `jobs` drapes side by side.
void PrintPopulationTable(const std::vector<v1::Garment>& imported, const std::vector<Body>& bodies,
                          const std::vector<std::string>& size_list, int jobs,
                          const std::string& rows_path, const workers::ClothSettings& settings,
                          const workers::DrapeSchedule& schedule) {
  std::vector<DrapeTask> tasks;
  for (size_t g = 0; g < imported.size(); ++g)
    for (size_t b = 0; b < bodies.size(); ++b)
      for (size_t s = 0; s < size_list.size(); ++s) tasks.push_back({g, b, s});
  std::vector<v1::DrapeReport> reports(tasks.size());
  std::atomic<size_t> done{0};
  std::mutex progress_mutex;
  pipeline::ProgressReporter progress("drapes", static_cast<int64_t>(tasks.size()), std::cerr,
                                      pipeline::StderrIsTerminal());
  ForEachSideBySide(tasks.size(), jobs, [&](size_t i) {
    const DrapeTask& t = tasks[i];
    auto fit = workers::DrapeGarment(imported[t.garment], size_list[t.size],
                                     bodies[t.body].positions, settings, schedule);
    if (fit.ok())
      reports[i] = fit->report;
    else
      reports[i].set_method(std::string(fit.status().message()));
    std::lock_guard<std::mutex> lock(progress_mutex);
    progress.Update(static_cast<int64_t>(++done));
  });
  progress.Finish();
  if (!rows_path.empty()) WriteRows(rows_path, imported, bodies, size_list, tasks, reports);

  // Strain columns are over the unflagged drapes: |l/l0 - 1| mean and worst p99, and the
  // worst p99 of its stretch side alone.
  std::printf("\n%-22s %6s %9s %9s %9s %9s %9s %9s %8s %8s\n", "garment", "verts", "s/drape",
              "pen<0mm", "pen<1mm", "strain_m", "strain99", "stretch99", "flagged", "ease_mm");
  double all_seconds = 0, all_below0 = 0, all_below1 = 0;
  std::vector<double> ok_mean, ok_p99, ok_stretch, ok_compression;
  int flagged_total = 0;
  for (size_t g = 0; g < imported.size(); ++g) {
    double seconds = 0, below0 = 0, below1 = 0, strain = 0, p99 = 0, stretch = 0, ease = 0;
    int count = 0, flagged = 0, ok = 0;
    for (size_t i = 0; i < tasks.size(); ++i) {
      if (tasks[i].garment != g) continue;
      const v1::DrapeReport& r = reports[i];
      ++count;
      seconds += r.seconds();
      below0 = std::max(below0, r.penetration_below_0mm());
      below1 = std::max(below1, r.penetration_below_1mm());
      ease += r.ease_mean_mm();
      if (r.overstretched()) {
        ++flagged;
        continue;
      }
      ++ok;
      strain += r.strain_mean();
      p99 = std::max(p99, r.strain_p99());
      stretch = std::max(stretch, r.stretch_p99());
      ok_mean.push_back(r.strain_mean());
      ok_p99.push_back(r.strain_p99());
      ok_stretch.push_back(r.stretch_p99());
      ok_compression.push_back(r.compression_p99());
    }
    all_seconds += seconds;
    all_below0 = std::max(all_below0, below0);
    all_below1 = std::max(all_below1, below1);
    flagged_total += flagged;
    std::printf("%-22s %6d %9.2f %8.3f%% %8.3f%% %8.2f%% %8.2f%% %8.2f%% %5d/%-2d %8.1f\n",
                imported[g].name().c_str(), imported[g].template_mesh().vertex_count(),
                seconds / count, 100 * below0, 100 * below1, ok ? 100 * strain / ok : 0.0,
                100 * p99, 100 * stretch, flagged, count, ease / count);
  }
  double mean_strain = 0;
  for (double m : ok_mean) mean_strain += m;
  auto worst = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  auto over_8 = [](const std::vector<double>& v) {
    return std::count_if(v.begin(), v.end(), [](double x) { return x > 0.08; });
  };
  std::printf(
      "\n%zu drapes (%zu garments x %zu bodies x %zu sizes): %.2f s per drape on one "
      "core; worst penetration <0 mm %.3f%%, <1 mm %.3f%%; %d flagged (stretch p99 > "
      "15%%)\nunflagged: strain mean %.2f%%; worst p99 of strain %.2f%%, of stretch "
      "%.2f%%, of compression %.2f%%; p99 over 8%% in %td (strain), %td (stretch)\n",
      tasks.size(), imported.size(), bodies.size(), size_list.size(),
      all_seconds / static_cast<double>(tasks.size()), 100 * all_below0, 100 * all_below1,
      flagged_total, ok_mean.empty() ? 0 : 100 * mean_strain / ok_mean.size(), 100 * worst(ok_p99),
      100 * worst(ok_stretch), 100 * worst(ok_compression), over_8(ok_p99), over_8(ok_stretch));
  std::printf("per body (mean over garments and sizes):\n");
  for (size_t b = 0; b < bodies.size(); ++b) {
    double ease = 0, strain = 0;
    int count = 0, flagged = 0;
    for (size_t i = 0; i < tasks.size(); ++i) {
      if (tasks[i].body != b) continue;
      ++count;
      ease += reports[i].ease_mean_mm();
      strain += reports[i].strain_mean();
      flagged += reports[i].overstretched();
    }
    std::printf("  %-12s ease %6.1f mm  strain mean %5.2f%%  flagged %d/%d\n",
                bodies[b].name.c_str(), ease / count, 100 * strain / count, flagged, count);
  }
}

// The second difference |D(b + d) + D(b - d) - 2 D(b)| per vertex (its largest coordinate),
// mm.
std::vector<double> SecondDifference(const core::Positions& plus, const core::Positions& minus,
                                     const core::Positions& mid) {
  const core::Positions diff = plus + minus - 2 * mid;
  std::vector<double> second(static_cast<size_t>(diff.rows()));
  for (Eigen::Index v = 0; v < diff.rows(); ++v)
    second[v] = 1000 * diff.row(v).cwiseAbs().maxCoeff();
  return second;
}

// How the vertices over 1 mm at step d scale when the step halves: a smooth map quarters the
// second difference, a kink (a contact starting or ending between the bodies) at least halves
// it. One that stays (ratio under sqrt 2) is a jump, or kinks of both signs within the step
// (a shirt front that leaves the belly, then swings less): the drapes between tell them apart.
struct Scaling {
  int steady = 0;
  int kinks = 0;
  double worst_ratio = 0;  // Of the worst vertex at d.
};

Scaling ClassifyScaling(const std::vector<double>& full, const std::vector<double>& half) {
  Scaling scaling;
  size_t worst = 0;
  for (size_t v = 0; v < full.size(); ++v) {
    if (full[v] > full[worst]) worst = v;
    if (full[v] <= 1.0) continue;
    const double ratio = full[v] / std::max(half[v], 1e-9);
    if (ratio < std::sqrt(2.0)) {
      ++scaling.steady;
    } else if (ratio < 2 * std::sqrt(2.0)) {
      ++scaling.kinks;
    }
  }
  scaling.worst_ratio = full[worst] / std::max(half[worst], 1e-9);
  return scaling;
}

// Where the smoothness is taken: the average body of a garment's wearers moved `sigmas`
// standard deviations along `component`.
struct SmoothnessPoint {
  int component = 0;
  double sigmas = 0;
};

// "C:S,C:S,...", each a component and a signed multiple of its sigma, |S| <= 3.
absl::StatusOr<std::vector<SmoothnessPoint>> ParseSmoothnessPoints(const std::string& text,
                                                                   int components) {
  std::vector<SmoothnessPoint> points;
  for (absl::string_view item : absl::StrSplit(text, ',')) {
    const std::vector<std::string> parts = absl::StrSplit(item, ':');
    SmoothnessPoint point;
    if (parts.size() != 2 || !absl::SimpleAtoi(parts[0], &point.component) ||
        !absl::SimpleAtod(parts[1], &point.sigmas) || !std::isfinite(point.sigmas)) {
      return absl::InvalidArgumentError(absl::StrCat(
          "--smoothness-at: '", item, "' is not COMPONENT:SIGMAS (e.g. 0:-0.3)"));
    }
    if (point.component < 0 || point.component >= components) {
      return absl::InvalidArgumentError(absl::StrCat("--smoothness-at: component ",
                                                     point.component, " is not in 0..",
                                                     components - 1));
    }
    if (std::abs(point.sigmas) > 3) {
      return absl::InvalidArgumentError(absl::StrCat(
          "--smoothness-at: ", point.sigmas, " sigma is beyond the population's +-3"));
    }
    points.push_back(point);
  }
  return points;
}

// Per garment, on the average body of the garment's wearers (man for male_*, else woman), or
// on each of `around` when given, moved to each point: a men's suit on a woman is a poor fit
// whose folds say little about the solver. The step d is 0.1 sigma along the point's component. One
// point says little: a fold that snaps between two resting places does so somewhere along a line of
// bodies (female_casualsuit01's p99: 1.2 mm at the average woman, 9.5 mm 0.3 sigma below her along
// component 0, simulator fitbase-newton-13). The second difference is also taken at half the step,
// to tell kinks from jumps (ClassifyScaling). With more than one point, a summary gives each
// garment's worst.
void PrintSmoothness(const std::vector<v1::Garment>& imported, const std::vector<Body>& bodies,
                     const std::vector<Body>& around, const v1::AvatarBasis& basis,
                     const std::vector<SmoothnessPoint>& points, const std::string& size, int jobs,
                     const workers::ClothSettings& settings,
                     const workers::DrapeSchedule& schedule) {
  auto pca = proto::PcaBasisFromProto(basis);
  struct Worst {
    double p99 = 0, max = 0, budget = 0;
    std::string where;
    int over_2mm = 0;
  };
  std::vector<Worst> worst(imported.size());
  // The p99 of the drapes flagged too small and of the others, per garment, around `around`.
  std::vector<std::vector<double>> flagged_p99(imported.size()), fitting_p99(imported.size());
  const size_t places = points.size() * std::max<size_t>(1, around.size());
  workers::DrapeSchedule twice = schedule;
  twice.homotopy_steps *= 2;
  twice.relax_steps *= 2;
  for (const SmoothnessPoint& point : points) {
    const double sigma = std::sqrt(pca->variances(point.component));
    const Eigen::VectorXd step = 0.1 * sigma * pca->components.col(point.component);
    const core::Positions delta =
        Eigen::Map<const core::Positions>(step.data(), step.size() / 3, 3);
    const std::string where = absl::StrFormat("%d:%+.2f", point.component, point.sigmas);
    std::printf(
        "\nsmoothness, size %s, around %s %+.2f sigma along component %d, d = "
        "0.1 sigma along it (mm; body moves %.1f mm mean, %.1f max):\n",
        size.c_str(), around.empty() ? "the average body" : "each avatar", point.sigmas,
        point.component, 1000 * delta.rowwise().norm().mean(),
        1000 * delta.rowwise().norm().maxCoeff());
    std::printf("%-22s %-12s %12s %12s %9s %13s %13s %10s %11s %15s %11s %12s\n", "garment", "body",
                "2nd_diff_max", "2nd_diff_p99", "over_1mm", "half_d_max", "half_d_p99", "max/half",
                "steady/kinks", "budget_x2_mean", "girth_ratio", "stretch_p99");
    for (size_t gi = 0; gi < imported.size(); ++gi) {
      const v1::Garment& g = imported[gi];
      std::vector<const Body*> centers;
      for (const Body& body : around) centers.push_back(&body);
      if (around.empty()) {
        const bool male = absl::StartsWith(g.name(), "male_");
        centers.push_back(&*std::find_if(bodies.begin(), bodies.end(), [&](const Body& b) {
          return b.name == (male ? "man" : "woman");
        }));
      }
      for (const Body* center : centers) {
        const Body& body = *center;
        const core::Positions b = body.positions + (point.sigmas / 0.1) * delta;
        struct Run {
          core::Positions body;
          workers::DrapeSchedule schedule;
          absl::StatusOr<workers::GarmentFit> fit = absl::UnknownError("not run");
        };
        std::vector<Run> runs = {
            {b, schedule}, {b + delta, schedule},       {b - delta, schedule},
            {b, twice},    {b + 0.5 * delta, schedule}, {b - 0.5 * delta, schedule}};
        ForEachSideBySide(runs.size(), jobs, [&](size_t i) {
          runs[i].fit = workers::DrapeGarment(g, size, runs[i].body, settings, runs[i].schedule);
        });
        if (const auto failed =
                std::find_if(runs.begin(), runs.end(), [](const Run& r) { return !r.fit.ok(); });
            failed != runs.end()) {
          std::printf("%-22s %-12s %s\n", g.name().c_str(), body.name.c_str(),
                      std::string(failed->fit.status().message()).c_str());
          continue;
        }
        const core::Positions& mid = runs[0].fit->positions;
        const std::vector<double> full =
            SecondDifference(runs[1].fit->positions, runs[2].fit->positions, mid);
        const std::vector<double> half =
            SecondDifference(runs[4].fit->positions, runs[5].fit->positions, mid);
        const Scaling scaling = ClassifyScaling(full, half);
        const double over = static_cast<double>(std::count_if(full.begin(), full.end(),
                                                              [](double mm) { return mm > 1.0; })) /
                            static_cast<double>(full.size());
        const double budget = 1000 * (runs[3].fit->positions - mid).rowwise().norm().mean();
        const double p99 = workers::Quantile(full, 0.99);
        const double max = *std::max_element(full.begin(), full.end());
        const v1::DrapeReport& report = runs[0].fit->report;
        std::printf(
            "%-22s %-12s %12.3f %12.3f %8.1f%% %13.3f %13.3f %10.2f %5d/%-5d %15.3f %11.3f "
            "%11.1f%%%s\n",
            g.name().c_str(), body.name.c_str(), max, p99, 100 * over,
            *std::max_element(half.begin(), half.end()), workers::Quantile(half, 0.99),
            scaling.worst_ratio, scaling.steady, scaling.kinks, budget,
            report.carried_girth_ratio(), 100 * report.stretch_p99(),
            report.overstretched() ? " too small" : "");
        (report.overstretched() ? flagged_p99 : fitting_p99)[gi].push_back(p99);
        Worst& w = worst[gi];
        if (p99 > w.p99) {
          w.p99 = p99;
          w.where = around.empty() ? where : absl::StrCat(body.name, " ", where);
        }
        w.max = std::max(w.max, max);
        w.budget = std::max(w.budget, budget);
        w.over_2mm += p99 > 2.0;
      }
    }
  }
  if (!around.empty()) {
    std::printf("\nsmoothness around the %zu avatars, median 2nd_diff_p99 (mm):\n", around.size());
    std::printf("%-22s %22s %22s\n", "garment", "flagged too small", "the others");
    const auto median = [](std::vector<double> values) {
      return values.empty()
                 ? std::string("-")
                 : absl::StrFormat("%.2f of %zu", workers::Quantile(values, 0.5), values.size());
    };
    for (size_t gi = 0; gi < imported.size(); ++gi) {
      std::printf("%-22s %22s %22s\n", imported[gi].name().c_str(), median(flagged_p99[gi]).c_str(),
                  median(fitting_p99[gi]).c_str());
    }
  }
  if (places < 2) return;
  std::printf("\nsmoothness over the %zu points (COMPONENT:SIGMAS), worst of each garment:\n",
              places);
  std::printf("%-22s %12s %22s %12s %15s %15s\n", "garment", "2nd_diff_p99", "at",
              "2nd_diff_max", "p99_over_2mm", "budget_x2_mean");
  for (size_t gi = 0; gi < imported.size(); ++gi) {
    const Worst& w = worst[gi];
    std::printf("%-22s %12.3f %22s %12.3f %9d of %-3zu %15.3f\n", imported[gi].name().c_str(),
                w.p99, w.where.c_str(), w.max, w.over_2mm, places, w.budget);
  }
}

bool IsMenswear(const v1::Garment& garment) { return absl::StartsWith(garment.name(), "male_"); }

// Where a garment's waistbands and collars sit on the skin under them. The landmarks move
// over the skin from one body to the next (on a heavy man the navel sinks towards the crotch),
// so a band that keeps to its skin changes place on the rise. This follows the skin points
// under the openings on the mean avatar's drape (the same triangle and barycentric point on
// every body) and takes the openings' mean height above them.
class SkinUnderSupports {
 public:
  // garment: as imported; mean_body: its mean avatar's body (13,380 x 3, m); mean_drape: its
  // drape on it (V x 3, m); triangles: the body's. An error when the garment message is
  // inconsistent.
  static absl::StatusOr<SkinUnderSupports> Of(const v1::Garment& garment,
                                              const core::Positions& mean_body,
                                              const core::Positions& mean_drape,
                                              const core::Triangles& triangles) {
    auto mesh = proto::GarmentTemplateFromProto(garment);
    if (!mesh.ok()) return mesh.status();
    auto model = workers::BuildClothModel(mesh->mesh.positions, mesh->mesh.faces,
                                          workers::ClothSettings().areal_density);
    if (!model.ok()) return model.status();
    auto supports = workers::FindSupports(*model, mesh->mesh.positions, mean_body);
    if (!supports.ok()) return supports.status();
    auto bvh = core::TriangleBvh::Build(mean_body, triangles);
    if (!bvh.ok()) return bvh.status();
    SkinUnderSupports skin;
    for (size_t o = 0; o < model->openings.size(); ++o) {
      const workers::Opening& opening = model->openings[o];
      std::vector<Under>* under = supports->IsWaistband(opening) ? &skin.band_
                                  : supports->IsCollar(static_cast<int32_t>(o)) ? &skin.collar_
                                                                                 : nullptr;
      if (under == nullptr) continue;
      for (int32_t v : opening.vertices) {
        const core::SurfacePoint hit = bvh->Closest(mean_drape.row(v).transpose(), 1.0);
        if (hit.found) under->push_back({v, hit.triangle, hit.barycentric});
      }
    }
    skin.triangles_ = triangles;
    return skin;
  }

  // Mean height of the band's (collar's) vertices in `drape` above the skin under them on
  // `body`, m; nullopt for a garment without one.
  std::optional<double> BandAboveSkin(const core::Positions& drape,
                                      const core::Positions& body) const {
    return Above(band_, drape, body);
  }
  std::optional<double> CollarAboveSkin(const core::Positions& drape,
                                        const core::Positions& body) const {
    return Above(collar_, drape, body);
  }

 private:
  struct Under {
    int32_t vertex;
    int32_t triangle;
    Eigen::Vector3d barycentric;
  };

  std::optional<double> Above(const std::vector<Under>& under, const core::Positions& drape,
                              const core::Positions& body) const {
    if (under.empty()) return std::nullopt;
    double sum = 0;
    for (const Under& u : under) {
      double skin = 0;
      for (int c = 0; c < 3; ++c) skin += u.barycentric(c) * body(triangles_(u.triangle, c), 1);
      sum += drape(u.vertex, 1) - skin;
    }
    return sum / static_cast<double>(under.size());
  }

  std::vector<Under> band_, collar_;
  core::Triangles triangles_;
};

// The tallest, shortest and heaviest `tail` of `count` avatars of a calibrated preset (seed 1),
// by the measurements the sampler calibrated them to.
std::vector<Body> ExtremeBodies(const body::BodyModel& model,
                                const body::PopulationSampler& sampler,
                                body::PopulationPreset preset, int count, int tail) {
  struct Sampled {
    int index;
    double stature, weight;
  };
  std::vector<Sampled> sampled;
  pipeline::ProgressReporter progress("avatars", count, std::cerr, pipeline::StderrIsTerminal());
  for (int i = 0; i < count; ++i) {
    auto avatar = sampler.SampleCalibrated(preset, 1, static_cast<uint64_t>(i));
    if (avatar.ok()) sampled.push_back({i, avatar->measured[0], avatar->measured[1]});
    progress.Update(i + 1);
  }
  progress.Finish();
  const std::string name(body::PopulationPresetName(preset));
  std::vector<Body> bodies;
  std::vector<int> taken;
  auto take = [&](const char* kind, auto better) {
    std::vector<Sampled> order = sampled;
    std::stable_sort(order.begin(), order.end(), better);
    for (int k = 0; k < tail && k < static_cast<int>(order.size()); ++k) {
      if (std::find(taken.begin(), taken.end(), order[k].index) != taken.end()) continue;
      taken.push_back(order[k].index);
      auto params = sampler.Sample(preset, 1, static_cast<uint64_t>(order[k].index));
      auto body = params.ok() ? model.BuildBody(*params) : params.status();
      if (!body.ok()) continue;
      bodies.push_back({absl::StrFormat("%s-%s-%03d", name, kind, order[k].index),
                        body->positions});
    }
  };
  take("tall", [](const Sampled& a, const Sampled& b) { return a.stature > b.stature; });
  take("short", [](const Sampled& a, const Sampled& b) { return a.stature < b.stature; });
  take("heavy", [](const Sampled& a, const Sampled& b) { return a.weight > b.weight; });
  return bodies;
}

// Where each garment's supports sit on bodies far from the mean, against the mean avatar.
void PrintSupports(const body::BodyModel& model, const std::vector<v1::Garment>& imported,
                   const std::vector<Body>& bench_bodies, const std::vector<std::string>& sizes,
                   int extremes, int jobs, const workers::ClothSettings& settings,
                   const workers::DrapeSchedule& schedule) {
  auto sampler = body::PopulationSampler::Create(model);
  if (!sampler.ok()) {
    std::cerr << sampler.status().message() << "\n";
    return;
  }
  const std::vector<Body> women =
      ExtremeBodies(model, *sampler, body::PopulationPreset::kWomen, 500, extremes);
  const std::vector<Body> men =
      ExtremeBodies(model, *sampler, body::PopulationPreset::kMen, 500, extremes);
  const core::Triangles triangles = core::Triangulate(model.body_faces());
  struct Row {
    size_t garment;
    Body body;
    std::string size;
    absl::StatusOr<workers::GarmentFit> fit = absl::UnknownError("not run");
    double inside_leg = 0;
    pipeline::SkinVisibility skin;  // Through the drape's own cloth.
  };
  std::vector<core::Triangles> garment_triangles;
  for (const v1::Garment& garment : imported) {
    auto mesh = proto::MeshFromProto(garment.template_mesh());
    garment_triangles.push_back(mesh.ok() ? core::Triangulate(mesh->faces) : core::Triangles());
  }
  std::vector<Row> rows;
  std::vector<double> mean_rise(imported.size(), 0.0);  // Crotch to navel, m.
  for (size_t g = 0; g < imported.size(); ++g) {
    auto mean = proto::MeshFromProto(imported[g].mean_avatar());
    if (!mean.ok()) continue;
    mean_rise[g] = workers::Rise(mean->positions);
    std::vector<Body> bodies = {{"mean", mean->positions.topRows(body::kBodyVertexCount)}};
    for (const Body& b : bench_bodies) {
      if (absl::StartsWith(b.name, "man") == IsMenswear(imported[g])) bodies.push_back(b);
    }
    for (const Body& b : IsMenswear(imported[g]) ? men : women) bodies.push_back(b);
    for (const Body& b : bodies) {
      for (const std::string& size : sizes) rows.push_back({g, b, size});
    }
  }
  std::atomic<size_t> done{0};
  std::mutex progress_mutex;
  pipeline::ProgressReporter progress("drapes", static_cast<int64_t>(rows.size()), std::cerr,
                                      pipeline::StderrIsTerminal());
  ForEachSideBySide(rows.size(), jobs, [&](size_t i) {
    Row& row = rows[i];
    row.fit = workers::DrapeGarment(imported[row.garment], row.size, row.body.positions, settings,
                                    schedule);
    const std::array<body::Measurement, 1> leg = {body::Measurement::kInsideLeg};
    auto measured = body::MeasureBody(row.body.positions, triangles, leg);
    if (measured.ok()) row.inside_leg = (*measured)[static_cast<int>(leg[0])];
    if (row.fit.ok()) {
      auto skin = pipeline::MeasureSkinThroughCloth({&row.body.positions, &triangles,
                                                     &row.fit->positions,
                                                     &garment_triangles[row.garment]});
      if (skin.ok()) row.skin = *skin;
    }
    std::lock_guard<std::mutex> lock(progress_mutex);
    progress.Update(static_cast<int64_t>(++done));
  });
  progress.Finish();

  std::printf(
      "\nsupports: drapes on the mean avatar, 5 bench bodies and the tallest, shortest and "
      "heaviest %d of 500 sampled avatars of the wearers' preset; worst |change| from the mean "
      "avatar's drape of the same size, cm (band_rise: the waistband's place as a share of the "
      "crotch-to-navel rise, in cm of the mean avatar's rise; rise_fit and collar_fit: the same "
      "over the drapes not flagged too small; band_skin and collar_skin: the height above the "
      "skin under it on the mean avatar, SkinUnderSupports, and the same not flagged); skin "
      "through the cloth (front and side, 600 px), all drapes' pixels together and the worst "
      "drape\n",
      extremes);
  std::printf("%-22s %-4s %6s %8s %9s %9s %10s %10s %9s %10s %9s %8s %11s %12s %9s %10s "
              "%10s %7s\n",
              "garment", "size", "drapes", "flagged", "pen<0mm", "pen<1mm", "waistband",
              "band_rise", "rise_fit", "band_skin", "skin_fit", "collar", "collar_fit",
              "collar_skin", "skin_fit", "skin_all", "skin_worst", "failed");
  for (size_t g = 0; g < imported.size(); ++g) {
    for (const std::string& size : sizes) {
      const Row* mean_row = nullptr;
      for (const Row& r : rows) {
        if (r.garment == g && r.size == size && r.body.name == "mean" && r.fit.ok()) mean_row = &r;
      }
      const v1::DrapeReport* mean = mean_row != nullptr ? &mean_row->fit->report : nullptr;
      std::optional<SkinUnderSupports> under;
      std::optional<double> band_on_mean, collar_on_mean;
      if (mean_row != nullptr) {
        auto found = SkinUnderSupports::Of(imported[g], mean_row->body.positions,
                                           mean_row->fit->positions, triangles);
        if (found.ok()) {
          under = *std::move(found);
          band_on_mean = under->BandAboveSkin(mean_row->fit->positions, mean_row->body.positions);
          collar_on_mean =
              under->CollarAboveSkin(mean_row->fit->positions, mean_row->body.positions);
        }
      }
      // Worst |change| of a height above the skin from the mean avatar's, cm, over all drapes
      // and over those not flagged too small.
      double band_skin = -1, band_skin_fit = -1, collar_skin = -1, collar_skin_fit = -1;
      auto skin_change = [](std::optional<double> here, std::optional<double> on_mean,
                            bool fits, double* all, double* fit) {
        if (!here || !on_mean) return;
        const double change = 100 * std::abs(*here - *on_mean);
        *all = std::max(*all, change);
        if (fits) *fit = std::max(*fit, change);
      };
      int count = 0, flagged = 0, failed = 0;
      double below0 = 0, below1 = 0, band = -1, band_share = -1, collar = -1, skin_worst = 0;
      double band_share_fit = -1, collar_fit = -1;  // Over the drapes not flagged.
      pipeline::SkinVisibility skin;
      for (const Row& r : rows) {
        if (r.garment != g || r.size != size) continue;
        if (!r.fit.ok()) {
          ++failed;
          continue;
        }
        const v1::DrapeReport& report = r.fit->report;
        ++count;
        if (under) {
          skin_change(under->BandAboveSkin(r.fit->positions, r.body.positions), band_on_mean,
                      !report.overstretched(), &band_skin, &band_skin_fit);
          skin_change(under->CollarAboveSkin(r.fit->positions, r.body.positions),
                      collar_on_mean, !report.overstretched(), &collar_skin, &collar_skin_fit);
        }
        flagged += report.overstretched();
        below0 = std::max(below0, report.penetration_below_0mm());
        below1 = std::max(below1, report.penetration_below_1mm());
        skin.cloth_pixels += r.skin.cloth_pixels;
        skin.skin_pixels += r.skin.skin_pixels;
        skin_worst = std::max(skin_worst, r.skin.share());
        if (mean != nullptr && report.has_waistband_above_navel_mm()) {
          band = std::max(band, std::abs(report.waistband_above_navel_mm() -
                                         mean->waistband_above_navel_mm()) / 10);
        }
        if (mean != nullptr && report.has_waistband_crotch_to_navel()) {
          const double change =
              std::abs(report.waistband_crotch_to_navel() - mean->waistband_crotch_to_navel());
          band_share = std::max(band_share, change);
          if (!report.overstretched()) band_share_fit = std::max(band_share_fit, change);
        }
        if (mean != nullptr && report.has_collar_above_neck_base_mm()) {
          const double change =
              std::abs(report.collar_above_neck_base_mm() - mean->collar_above_neck_base_mm()) /
              10;
          collar = std::max(collar, change);
          if (!report.overstretched()) collar_fit = std::max(collar_fit, change);
        }
      }
      auto cm = [](double v) { return v < 0 ? std::string("-") : absl::StrFormat("%.1f", v); };
      // The band's worst change of place on the torso, in centimetres of the mean avatar's
      // crotch-to-navel rise.
      auto rise_cm = [&](double share) { return share < 0 ? -1 : share * 100 * mean_rise[g]; };
      std::printf(
          "%-22s %-4s %6d %8d %8.3f%% %8.3f%% %10s %10s %9s %10s %9s %8s %11s %12s %9s %9.2f%% "
          "%9.2f%% %7d\n",
          imported[g].name().c_str(), size.c_str(), count, flagged, 100 * below0, 100 * below1,
          cm(band).c_str(), cm(rise_cm(band_share)).c_str(), cm(rise_cm(band_share_fit)).c_str(),
          cm(band_skin).c_str(), cm(band_skin_fit).c_str(), cm(collar).c_str(),
          cm(collar_fit).c_str(), cm(collar_skin).c_str(), cm(collar_skin_fit).c_str(),
          100 * skin.share(), 100 * skin_worst, failed);
    }
  }
  bool any_cuffs = false;
  for (const Row& r : rows) any_cuffs |= r.fit.ok() && r.fit->report.has_cuff_gap_mm();
  if (any_cuffs) {
    std::printf(
        "\ncuffs (declared at import): their vertices' mean distance from the skin, mm, on the "
        "mean avatar, averaged over the drapes and on the worst drape (the contact offset is "
        "%.1f); the leg cuffs' heights are the hem table's\n",
        1000 * settings.collision_offset);
    std::printf("%-22s %-4s %6s %6s %8s %8s %8s\n", "garment", "size", "drapes", "cuffs", "on_mean",
                "average", "worst");
    for (size_t g = 0; g < imported.size(); ++g) {
      for (const std::string& size : sizes) {
        int count = 0;
        uint32_t cuff_count = 0;
        double on_mean = -1, sum = 0, worst = 0;
        for (const Row& r : rows) {
          if (r.garment != g || r.size != size || !r.fit.ok()) continue;
          const v1::DrapeReport& report = r.fit->report;
          if (!report.has_cuff_gap_mm()) continue;
          ++count;
          cuff_count = report.cuff_count();
          sum += report.cuff_gap_mm();
          worst = std::max(worst, report.cuff_gap_mm());
          if (r.body.name == "mean") on_mean = report.cuff_gap_mm();
        }
        if (count == 0) continue;
        std::printf("%-22s %-4s %6d %6u %8.1f %8.1f %8.1f\n", imported[g].name().c_str(),
                    size.c_str(), count, cuff_count, on_mean, sum / count, worst);
      }
    }
  }
  std::printf(
      "\nleg hems above the ankle (cm) by inside leg (cm), size M, with the waistband above the "
      "navel and the collar above the neck base (cm):\n");
  for (size_t g = 0; g < imported.size(); ++g) {
    std::vector<const Row*> hems;
    for (const Row& r : rows) {
      if (r.garment == g && r.size == "M" && r.fit.ok() && r.fit->report.has_hem_above_ankle_mm())
        hems.push_back(&r);
    }
    if (hems.empty()) continue;
    std::sort(hems.begin(), hems.end(),
              [](const Row* a, const Row* b) { return a->inside_leg < b->inside_leg; });
    // Least-squares slope of the hem's height over the leg's length.
    double mx = 0, my = 0;
    for (const Row* r : hems) {
      mx += r->inside_leg;
      my += r->fit->report.hem_above_ankle_mm() / 1000;
    }
    mx /= static_cast<double>(hems.size());
    my /= static_cast<double>(hems.size());
    double sxy = 0, sxx = 0;
    for (const Row* r : hems) {
      sxy += (r->inside_leg - mx) * (r->fit->report.hem_above_ankle_mm() / 1000 - my);
      sxx += (r->inside_leg - mx) * (r->inside_leg - mx);
    }
    std::printf("%s: %.2f cm higher per cm of leg\n", imported[g].name().c_str(),
                sxx > 0 ? sxy / sxx : 0.0);
    for (const Row* r : hems) {
      const v1::DrapeReport& report = r->fit->report;
      std::string supports;
      if (report.has_waistband_above_navel_mm()) {
        supports += absl::StrFormat("  waistband %+5.1f (%3.0f%% of the rise)",
                                    report.waistband_above_navel_mm() / 10,
                                    100 * report.waistband_crotch_to_navel());
      }
      if (report.has_collar_above_neck_base_mm()) {
        supports += absl::StrFormat("  collar %+5.1f", report.collar_above_neck_base_mm() / 10);
      }
      std::printf("  %-20s inside leg %5.1f  hem %+5.1f%s  stretch p99 %3.0f%%  skin %.2f%%\n",
                  r->body.name.c_str(), 100 * r->inside_leg, report.hem_above_ankle_mm() / 10,
                  supports.c_str(), 100 * report.stretch_p99(), 100 * r->skin.share());
    }
  }
}

// The two factorisations, and the capped path against every step solved, on each garment in
// one run.
void PrintSpeed(const std::vector<v1::Garment>& imported, const std::vector<Body>& bodies,
                const workers::ClothSettings& settings, const workers::DrapeSchedule& schedule) {
  std::printf(
      "\nspeed, size M on the wearers' average body, one drape at a time (s): the factorisations "
      "(simplicial against supernodal, both with the path's iterations capped at %d), then the "
      "path's steps each solved to the tolerance (up to %d iterations, the solver before "
      "fitbase-newton-9) against capped:\n",
      settings.path_newton_iterations, settings.newton_iterations);
  std::printf("%-22s %6s %11s %11s %7s %11s %7s %10s %10s %8s\n", "garment", "verts",
              "simplicial", "supernodal", "ratio", "solved", "ratio", "apart_mm", "moved_mm",
              "repeat");
  double total_simplicial = 0, total_supernodal = 0, total_solved = 0;
  for (const v1::Garment& g : imported) {
    const Body& body = *std::find_if(bodies.begin(), bodies.end(), [&](const Body& b) {
      return b.name == (IsMenswear(g) ? "man" : "woman");
    });
    workers::ClothSettings simplicial = settings;
    simplicial.factorization = workers::Factorization::kSimplicialLdlt;
    workers::ClothSettings supernodal = settings;
    supernodal.factorization = workers::Factorization::kSupernodalCholmod;
    workers::ClothSettings solved = supernodal;
    solved.path_newton_iterations = solved.newton_iterations;
    auto timed = [&](const workers::ClothSettings& settings, double* seconds) {
      const auto start = std::chrono::steady_clock::now();
      auto fit = workers::DrapeGarment(g, "M", body.positions, settings, schedule);
      *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return fit;
    };
    double simplicial_s = 0, supernodal_s = 0, solved_s = 0, again_s = 0;
    auto simplicial_fit = timed(simplicial, &simplicial_s);
    auto supernodal_fit = timed(supernodal, &supernodal_s);
    auto solved_fit = timed(solved, &solved_s);
    auto again = timed(supernodal, &again_s);
    if (!simplicial_fit.ok() || !supernodal_fit.ok() || !solved_fit.ok() || !again.ok()) {
      std::printf("%-22s failed\n", g.name().c_str());
      continue;
    }
    total_simplicial += simplicial_s;
    total_supernodal += supernodal_s;
    total_solved += solved_s;
    // apart: the two factorisations' drapes, worst vertex; moved: the capped path's drape
    // against every step solved, mean over the vertices.
    std::printf(
        "%-22s %6d %11.2f %11.2f %6.2fx %11.2f %6.2fx %10.4f %10.4f %8s\n", g.name().c_str(),
        g.template_mesh().vertex_count(), simplicial_s, supernodal_s,
        simplicial_s / supernodal_s, solved_s, solved_s / supernodal_s,
        1000 * (simplicial_fit->positions - supernodal_fit->positions).rowwise().norm().maxCoeff(),
        1000 * (solved_fit->positions - supernodal_fit->positions).rowwise().norm().mean(),
        again->positions == supernodal_fit->positions ? "bitwise" : "DIFFERS");
  }
  if (total_supernodal > 0) {
    std::printf("all: %.1f s simplicial, %.1f s supernodal (%.2fx), %.1f s solved (%.2fx)\n",
                total_simplicial, total_supernodal, total_simplicial / total_supernodal,
                total_solved, total_solved / total_supernodal);
  }
}

int Main(int argc, char** argv) {
  CLI::App app{"Offline fitter figures over the shared garments"};
  std::string basis_path, data = "data/makehuman", garments = "all", sizes = "S,M,XL", out, rows;
  int jobs = 2;
  bool smoothness = false, smoothness_only = false, supports = false, speed = false;
  bool unsupported = false;
  int extremes = 10;
  std::string cuffs;
  workers::ClothSettings settings;
  workers::DrapeSchedule schedule;
  app.add_option("--basis", basis_path, "Avatar basis (.fbb) with avatar parameters")->required();
  app.add_option("--data", data, "MakeHuman data folder");
  app.add_option("--garments", garments, "Comma-separated garment names, or all");
  app.add_option("--sizes", sizes, "Sizes to drape");
  app.add_option("--jobs", jobs, "Drapes run side by side (each single-threaded)")
      ->check(CLI::Range(1, 64));
  app.add_flag("--smoothness", smoothness, "Also measure smoothness and budget doubling");
  app.add_flag("--smoothness-only", smoothness_only, "Only measure smoothness and budget doubling");
  std::string smoothness_at = "0:0", smoothness_around, smoothness_size = "M";
  app.add_option("--smoothness-at", smoothness_at,
                 "Where the smoothness is taken: COMPONENT:SIGMAS,... from the average body "
                 "(default: 0:0)");
  app.add_option("--smoothness-around", smoothness_around,
                 "Take the smoothness around every avatar of this population folder, each moved "
                 "by the --smoothness-at points, instead of around the average body");
  app.add_option("--smoothness-size", smoothness_size,
                 "The size the smoothness is taken in, one of --sizes (default: M)");
  app.add_flag("--supports", supports,
               "Only measure where supports sit on bodies far from the mean (with --sizes)");
  app.add_option("--extremes", extremes,
                 "Tallest, shortest and heaviest avatars of 500 per preset for --supports")
      ->check(CLI::Range(0, 500));
  app.add_flag("--speed", speed,
               "Only compare the factorisations' speed, and the capped path against every step "
               "solved");
  app.add_option("--homotopy-steps", schedule.homotopy_steps,
                 absl::StrCat("Drape steps moving the body from the mean avatar, in every drape "
                              "(default: ",
                              schedule.homotopy_steps, ")"))
      ->check(CLI::Range(1, 1000));
  app.add_option("--path-iterations", settings.path_newton_iterations,
                 "Newton iterations per step while the body moves (default: ClothSettings's)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--friction", settings.friction,
                 "Coulomb friction's mu in place of the stiction (0: the stiction, the default)")
      ->check(CLI::Range(0.0, workers::kMaxFriction));
  app.add_option("--cuff-friction", settings.cuff_friction,
                 "Coulomb friction's mu on declared cuffs on top of their ties (0: the ties alone, "
                 "the default)")
      ->check(CLI::Range(0.0, workers::kMaxFriction));
  app.add_option("--skin-tie", settings.skin_tie,
                 "Stiction, N/m per kg of cloth (default: ClothSettings's)")
      ->check(CLI::Range(0.0, workers::kMaxSkinTie));
  app.add_option("--tight-tie-factor", settings.tight_tie_factor,
                 "How many times firmer the ties and supports are on a size too small for the "
                 "body (1: never; default: ClothSettings's)");
  app.add_option("--tight-girth-from", settings.tight_girth_from,
                 "Carried girth ratio where the ties start to firm (default: ClothSettings's)");
  app.add_option("--tight-girth-full", settings.tight_girth_full,
                 "Carried girth ratio where they reach --tight-tie-factor (default: "
                 "ClothSettings's)");
  CLI::Option* anchor =
      app.add_option("--anchor", settings.anchor_stiffness,
                     "N/m holding a collar's height on the body (default: ClothSettings's)")
          ->check(CLI::PositiveNumber);
  CLI::Option* band_stiffness =
      app.add_option("--waistband-stiffness", settings.waistband_stiffness,
                     "N/m of a waistband's elastic (0: none; default: ClothSettings's)");
  CLI::Option* band_grip =
      app.add_option("--waistband-grip", settings.waistband_grip,
                     "A waistband elastic's rest length as a share of the band's")
          ->check(CLI::Range(0.01, 1.0));
  CLI::Option* band_anchor =
      app.add_option("--waistband-anchor", settings.waistband_anchor_stiffness,
                     "N/m holding an elastic waistband's height (default: ClothSettings's)");
  app.add_flag("--unsupported", unsupported,
               "Drape without the supports (workers::WithoutSupports), as before them")
      ->excludes(anchor)
      ->excludes(band_stiffness)
      ->excludes(band_grip)
      ->excludes(band_anchor);
  app.add_option("--cuffs", cuffs,
                 "Import every garment with these openings declared elastic cuffs: sleeves, "
                 "legs or both (fitbase garment import --cuffs)");
  app.add_option("--out", out, "Folder for the imported garments (reused when present)");
  app.add_option("--rows", rows, "CSV file for one row per drape of the population table");
  CLI11_PARSE(app, argc, argv);
  // CLI11's range lets NaN through.
  for (const auto& [mu, name] : {std::pair{settings.friction, "--friction"},
                                 std::pair{settings.cuff_friction, "--cuff-friction"}}) {
    if (absl::Status friction = workers::CheckFriction(mu, name); !friction.ok()) {
      std::cerr << friction.message() << "\n";
      return 2;
    }
  }
  if (absl::Status tie = workers::CheckSkinTie(settings.skin_tie, "--skin-tie"); !tie.ok()) {
    std::cerr << tie.message() << "\n";
    return 2;
  }
  if (absl::Status tight = workers::CheckTightTies(settings); !tight.ok()) {
    std::cerr << tight.message()
              << " (--tight-tie-factor, --tight-girth-from, --tight-girth-full)\n";
    return 2;
  }
  if (unsupported) settings = workers::WithoutSupports(settings);
  const absl::StatusOr<v1::ElasticCuffs> declared_cuffs = pipeline::ParseCuffs(cuffs);
  if (!declared_cuffs.ok()) {
    std::cerr << "--" << declared_cuffs.status().message() << "\n";
    return 2;
  }

  v1::AvatarBasis basis;
  if (auto s = proto::ReadMessageFile(basis_path, &basis); !s.ok()) {
    std::cerr << s.message() << "\n";
    return 1;
  }
  const absl::StatusOr<std::vector<SmoothnessPoint>> smoothness_points =
      ParseSmoothnessPoints(smoothness_at, static_cast<int>(basis.component_count()));
  if (!smoothness_points.ok()) {
    std::cerr << smoothness_points.status().message() << "\n";
    return 1;
  }
  auto model = body::BodyModel::Load(data);
  if (!model.ok()) {
    std::cerr << model.status().message() << "\n";
    return 1;
  }
  std::vector<std::string> names;
  if (garments == "all") {
    for (const auto& entry :
         std::filesystem::directory_iterator(std::filesystem::path(data) / "clothes")) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
  } else {
    names = absl::StrSplit(garments, ',');
  }
  const std::vector<std::string> size_list = absl::StrSplit(sizes, ',');
  if ((smoothness || smoothness_only) &&
      std::find(size_list.begin(), size_list.end(), smoothness_size) == size_list.end()) {
    std::cerr << "--smoothness-size " << smoothness_size << " is not one of --sizes " << sizes
              << "\n";
    return 2;
  }
  const std::vector<Body> bodies = TestBodies(*model);
  std::vector<Body> around;
  if (!smoothness_around.empty()) {
    const absl::StatusOr<pipeline::Population> population =
        pipeline::ReadPopulationFolder(smoothness_around);
    if (!population.ok()) {
      std::cerr << "--smoothness-around: " << population.status().message() << "\n";
      return 1;
    }
    for (size_t i = 0; i < population->avatar_files.size(); ++i) {
      const auto column = population->samples.col(static_cast<Eigen::Index>(i));
      around.push_back({population->avatar_files[i].stem().string(),
                        Eigen::Map<const core::Positions>(column.data(), column.size() / 3, 3)});
    }
  }
  if (!out.empty()) std::filesystem::create_directories(out);

  std::vector<v1::Garment> imported;
  for (const std::string& name : names) {
    const std::filesystem::path cache =
        out.empty() ? "" : std::filesystem::path(out) / (name + ".fbg");
    pipeline::GarmentImportPaths paths;
    paths.mhclo = std::filesystem::path(data) / "clothes" / name / (name + ".mhclo");
    absl::StatusOr<pipeline::GarmentImportRequest> request =
        pipeline::ReadGarmentImportFiles(paths);
    if (request.ok()) {
      request->sizes = size_list;
      request->cuffs = *declared_cuffs;
    }
    // A cached import is reused only if importing anew would give it the same id (same
    // basis, files, sizes and importer version).
    const absl::StatusOr<std::string> id =
        request.ok() ? pipeline::GarmentImportId(basis.id(), *request) : request.status();
    v1::Garment garment;
    if (id.ok() && !cache.empty() && proto::ReadMessageFile(cache, &garment).ok() &&
        garment.id() == *id) {
      imported.push_back(garment);
      continue;
    }
    absl::StatusOr<v1::Garment> result =
        id.ok() ? pipeline::ImportGarment(*model, basis, *request) : id.status();
    if (!result.ok()) {
      std::cerr << name << ": " << result.status().message() << "\n";
      return 1;
    }
    if (!cache.empty()) (void)proto::WriteMessageFile(cache, *result);
    imported.push_back(*std::move(result));
  }

  if (supports) {
    PrintSupports(*model, imported, bodies, size_list, extremes, jobs, settings, schedule);
    return 0;
  }
  if (speed) {
    PrintSpeed(imported, bodies, settings, schedule);
    return 0;
  }
  if (!smoothness_only) {
    PrintPopulationTable(imported, bodies, size_list, jobs, rows, settings, schedule);
  }
  if (smoothness || smoothness_only) {
    PrintSmoothness(imported, bodies, around, basis, *smoothness_points, smoothness_size, jobs,
                    settings, schedule);
  }
  return 0;
}

}  // namespace
}  // namespace fitbase

int main(int argc, char** argv) { return fitbase::Main(argc, argv); }
