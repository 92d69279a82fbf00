#include "body/body_measurements.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "Eigen/Geometry"
#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "body/body_model.h"

namespace fitbase::body {
namespace {

constexpr std::array<Measurement, kMeasurementCount> kAll = {
    Measurement::kStature,       Measurement::kWeight,       Measurement::kBustGirth,
    Measurement::kUnderbustGirth, Measurement::kWaistGirth,  Measurement::kHipGirth,
    Measurement::kThighGirth,    Measurement::kUpperArmGirth, Measurement::kNeckGirth,
    Measurement::kInsideLeg,     Measurement::kArmLength,    Measurement::kShoulderWidth,
    Measurement::kNavelWaistGirth,
};

constexpr std::array<absl::string_view, kMeasurementCount> kNames = {
    "stature",     "weight",     "bust_girth",      "underbust_girth",
    "waist_girth", "hip_girth",  "thigh_girth",     "upper_arm_girth",
    "neck_girth",  "inside_leg", "arm_length",      "shoulder_width",
    "navel_waist_girth",
};

// Heights of a band are sampled this far apart. On MakeHuman's default woman and man and three
// held-out women, a step five times finer moved one bust girth by 3 mm (a breast peaks sharply
// at the nipple) and every other girth by under 0.5 mm.
constexpr double kBandStep = 0.0025;

// How far an upper arm section's centroid lies from the midpoint of acromion and olecranon at
// most: the midpoint lies on the skin, and the thickest arms of the wide populations are under
// 14 cm across.
constexpr double kArmReach = 0.14;

// Signed area of a closed 2D polygon (positive counter-clockwise).
double SignedArea(const std::vector<Eigen::Vector2d>& loop) {
  double twice = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const Eigen::Vector2d& a = loop[i];
    const Eigen::Vector2d& b = loop[(i + 1) % loop.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return twice / 2;
}

// The centroid of a loop's points, in the section's plane.
Eigen::Vector2d Centroid(const std::vector<Eigen::Vector2d>& loop) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : loop) sum += p;
  return sum / static_cast<double>(loop.size());
}

// Heights [low, high] over which a girth's extreme is sought, m.
struct Band {
  double low;
  double high;
};

}  // namespace

bool LoopContains(const std::vector<Eigen::Vector2d>& loop, const Eigen::Vector2d& p) {
  bool inside = false;
  for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const Eigen::Vector2d& a = loop[i];
    const Eigen::Vector2d& b = loop[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

double LoopArea(const std::vector<Eigen::Vector2d>& loop) { return std::abs(SignedArea(loop)); }

double GirthAround(const PlaneSection& section, const Eigen::Vector3d& inside) {
  const Eigen::Vector3d d = inside - section.origin;
  const Eigen::Vector2d p(d.dot(section.u), d.dot(section.v));
  double best = std::numeric_limits<double>::quiet_NaN();
  double best_area = 0;
  for (const auto& loop : section.loops) {
    if (loop.size() < 3 || !LoopContains(loop, p)) continue;
    // Nested loops (an inner surface) cannot occur on a body; keep the largest anyway.
    const double area = std::abs(SignedArea(loop));
    if (area > best_area) {
      best_area = area;
      best = ConvexHullPerimeter(loop);
    }
  }
  return best;
}

absl::string_view MeasurementName(Measurement measurement) {
  return kNames[static_cast<int>(measurement)];
}

absl::StatusOr<Measurement> ParseMeasurement(absl::string_view name) {
  for (Measurement m : kAll) {
    if (MeasurementName(m) == name) return m;
  }
  return absl::InvalidArgumentError(absl::StrCat("unknown measurement '", name,
                                                 "'; known: ", absl::StrJoin(kNames, ", ")));
}

bool IsMass(Measurement measurement) { return measurement == Measurement::kWeight; }

absl::string_view TypedUnit(Measurement measurement) { return IsMass(measurement) ? "kg" : "cm"; }

double InTypedUnit(Measurement measurement, double value) {
  return IsMass(measurement) ? value : 100 * value;
}

std::span<const Measurement> AllMeasurements() { return kAll; }

double ConvexHullPerimeter(std::span<const Eigen::Vector2d> points) {
  if (points.size() < 2) return 0;
  std::vector<Eigen::Vector2d> sorted(points.begin(), points.end());
  std::sort(sorted.begin(), sorted.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  // Andrew's monotone chain: lower then upper hull, collinear points dropped.
  std::vector<Eigen::Vector2d> hull(2 * sorted.size());
  size_t k = 0;
  for (const Eigen::Vector2d& p : sorted) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (size_t i = sorted.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], sorted[i]) <= 0) --k;
    hull[k++] = sorted[i];
  }
  double perimeter = 0;
  for (size_t i = 0; i + 1 < k; ++i) perimeter += (hull[i + 1] - hull[i]).norm();
  return perimeter;
}

namespace {
PlaneSection SectionOf(const core::Positions& positions, const core::Triangles& triangles,
                       const std::vector<int32_t>* candidates, const Eigen::Vector3d& point,
                       const Eigen::Vector3d& normal);
}  // namespace

PlaneSection SectionMesh(const core::Positions& positions, const core::Triangles& triangles,
                         const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  return SectionOf(positions, triangles, nullptr, point, normal);
}

namespace {

PlaneSection SectionOf(const core::Positions& positions, const core::Triangles& triangles,
                       const std::vector<int32_t>* candidates, const Eigen::Vector3d& point,
                       const Eigen::Vector3d& normal) {
  PlaneSection section;
  const Eigen::Vector3d n = normal.normalized();
  section.origin = point;
  section.u = n.unitOrthogonal();
  section.v = n.cross(section.u);
  auto distance = [&](int32_t v) {
    return (positions(v, 0) - point.x()) * n.x() + (positions(v, 1) - point.y()) * n.y() +
           (positions(v, 2) - point.z()) * n.z();
  };

  // Each crossing lies on a mesh edge, so segments that share an edge join: keying points by
  // their edge separates loops by the mesh's connectivity, not by proximity.
  auto edge_key = [](int32_t a, int32_t b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
  };
  absl::flat_hash_map<uint64_t, int> point_of_edge;
  std::vector<Eigen::Vector2d> points;
  std::vector<SectionEdgePoint> on_edge;
  std::vector<std::array<int, 2>> links;  // Up to two neighbours per point.
  auto crossing = [&](int32_t a, int32_t b) {
    const uint64_t key = edge_key(a, b);
    auto [it, added] = point_of_edge.try_emplace(key, static_cast<int>(points.size()));
    if (added) {
      const double t = distance(a) / (distance(a) - distance(b));
      const Eigen::Vector3d x =
          positions.row(a).transpose() + t * (positions.row(b) - positions.row(a)).transpose() -
          point;
      points.emplace_back(x.dot(section.u), x.dot(section.v));
      on_edge.push_back({a, b, t});
      links.push_back({-1, -1});
    }
    return it->second;
  };
  auto link = [&](int p, int q) {
    for (auto [from, to] : {std::pair{p, q}, std::pair{q, p}}) {
      if (links[from][0] < 0) {
        links[from][0] = to;
      } else if (links[from][1] < 0) {
        links[from][1] = to;
      }
    }
  };
  const Eigen::Index count =
      candidates ? static_cast<Eigen::Index>(candidates->size()) : triangles.rows();
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::Index t = candidates ? (*candidates)[i] : i;
    int ends[2];
    int found = 0;
    for (int c = 0; c < 3 && found < 2; ++c) {
      const int32_t a = triangles(t, c);
      const int32_t b = triangles(t, (c + 1) % 3);
      // A vertex exactly on the plane counts as above it, so no crossing is found twice.
      if ((distance(a) >= 0) != (distance(b) >= 0)) ends[found++] = crossing(a, b);
    }
    if (found == 2) link(ends[0], ends[1]);
  }

  std::vector<bool> used(points.size(), false);
  for (size_t start = 0; start < points.size(); ++start) {
    if (used[start]) continue;
    // An open chain is walked from one of its ends, so that it comes out whole: first find
    // an end (on a closed loop the walk comes back to `start` and any point will do).
    int previous = -1;
    int current = static_cast<int>(start);
    for (size_t hops = 0; hops < points.size(); ++hops) {
      const int next = links[current][0] != previous ? links[current][0] : links[current][1];
      if (next < 0 || next == static_cast<int>(start)) break;
      previous = current;
      current = next;
    }
    const int first = current;
    std::vector<Eigen::Vector2d> loop;
    std::vector<SectionEdgePoint> edges;
    bool closed = false;
    previous = -1;
    while (current >= 0 && !used[current]) {
      used[current] = true;
      loop.push_back(points[current]);
      edges.push_back(on_edge[current]);
      const int next = links[current][0] != previous ? links[current][0] : links[current][1];
      previous = current;
      current = next;
      if (current == first) closed = true;
    }
    section.loops.push_back(std::move(loop));
    section.edges.push_back(std::move(edges));
    section.closed.push_back(closed);
  }
  return section;
}

}  // namespace

double EnclosedVolume(const core::Positions& positions, const core::Triangles& triangles) {
  double six_volume = 0;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::Vector3d a = positions.row(triangles(t, 0));
    const Eigen::Vector3d b = positions.row(triangles(t, 1));
    const Eigen::Vector3d c = positions.row(triangles(t, 2));
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6;
}

absl::StatusOr<BodyMeasurements> MeasureBody(const core::Mesh& body) {
  return MeasureBody(body.positions, core::Triangulate(body.faces), kAll);
}

absl::StatusOr<BodyMeasurements> MeasureBody(
    const core::Positions& positions, const core::Triangles& triangles,
    std::span<const Measurement> which,
    std::array<std::optional<GirthPlace>, kMeasurementCount>* places) {
  if (positions.rows() != kBodyVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("a body to measure has ", kBodyVertexCount,
                                                   " vertices (", kBodyTopologyId, "), not ",
                                                   positions.rows()));
  }
  if (!positions.allFinite()) {
    return absl::InvalidArgumentError("a body to measure has non-finite positions");
  }
  if (triangles.rows() == 0 || triangles.minCoeff() < 0 ||
      triangles.maxCoeff() >= positions.rows()) {
    return absl::InvalidArgumentError("a body to measure needs the faces of its topology");
  }
  using L = BodyLandmarks;
  auto at = [&](int32_t v) -> Eigen::Vector3d { return positions.row(v).transpose(); };
  const double floor = positions.col(1).minCoeff();
  const double top = positions.col(1).maxCoeff();
  const Eigen::Vector3d crotch = at(L::kCrotch);
  const Eigen::Vector3d navel = at(L::kNavel);
  const Eigen::Vector3d underbust = at(L::kLeftUnderbust);
  const Eigen::Vector3d bust = at(L::kLeftBustPoint);
  const Eigen::Vector3d acromion = at(L::kLeftAcromion);
  const Eigen::Vector3d olecranon = at(L::kLeftOlecranon);
  const Eigen::Vector3d wrist = at(L::kLeftWrist);

  // Torso girths are taken around the vertical line on the centre plane (x = 0; hm08 is
  // symmetric) 5 cm behind the band's front landmark: inside the torso at every height of
  // the band, even on thin bodies, and outside the arms.
  // Horizontal sections visit only the triangles of their height bin: a body's triangles span
  // at most a few centimetres, so a section reads a hundredth of the mesh.
  constexpr double kBin = 0.01;
  const int bins = static_cast<int>((top - floor) / kBin) + 1;
  std::vector<std::vector<int32_t>> by_height(bins);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    double low = top, high = floor;
    for (int c = 0; c < 3; ++c) {
      low = std::min(low, positions(triangles(t, c), 1));
      high = std::max(high, positions(triangles(t, c), 1));
    }
    const int last = std::min(bins - 1, static_cast<int>((high - floor) / kBin));
    for (int bin = static_cast<int>((low - floor) / kBin); bin <= last; ++bin) {
      by_height[bin].push_back(static_cast<int32_t>(t));
    }
  }
  auto horizontal = [&](const Eigen::Vector3d& point) {
    const int bin = std::clamp(static_cast<int>((point.y() - floor) / kBin), 0, bins - 1);
    return SectionOf(positions, triangles, &by_height[bin], point, Eigen::Vector3d::UnitY());
  };
  auto torso_girth = [&](double y, const Eigen::Vector3d& front) {
    const Eigen::Vector3d inside(0.0, y, front.z() - 0.05);
    return GirthAround(horizontal(inside), inside);
  };
  // Near the armpits a horizontal section of the torso runs into the arms, which the mesh
  // joins to it there: a chest girth counts only sections that stay inside the upper arms'
  // line (midway between acromion and elbow; a torso is narrower there even on heavy bodies).
  const double arm_line = (acromion.x() + olecranon.x()) / 2;
  // 10 cm behind the bust point: 5 cm can fall in the cleavage of a large bust.
  auto chest_girth = [&](double y, const Eigen::Vector3d& front) {
    const Eigen::Vector3d inside(0.0, y, front.z() - 0.10);
    const PlaneSection section = horizontal(inside);
    const Eigen::Vector3d d = inside - section.origin;
    const Eigen::Vector2d p(d.dot(section.u), d.dot(section.v));
    for (const auto& loop : section.loops) {
      if (loop.size() < 3 || !LoopContains(loop, p)) continue;
      for (const Eigen::Vector2d& q : loop) {
        const Eigen::Vector3d world = section.origin + q.x() * section.u + q.y() * section.v;
        if (std::abs(world.x()) > arm_line) return std::numeric_limits<double>::quiet_NaN();
      }
    }
    return GirthAround(section, inside);
  };
  // Where the girth being measured was taken; recorded only when asked for.
  std::optional<GirthPlace> place;
  auto record = [&](const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                    const Eigen::Vector3d& inside) {
    if (places != nullptr) place = GirthPlace{point, normal.normalized(), inside};
  };
  // The extreme girth over a band of heights; `place_at` records where, at the best height.
  auto extreme_over = [&](Band band, bool largest, auto&& girth_at, auto&& place_at) {
    double best = std::numeric_limits<double>::quiet_NaN();
    double best_y = band.low;
    const int steps = std::max(1, static_cast<int>(std::ceil((band.high - band.low) / kBandStep)));
    for (int i = 0; i <= steps; ++i) {
      const double y = band.low + (band.high - band.low) * i / steps;
      const double g = girth_at(y);
      if (std::isnan(g)) continue;
      if (std::isnan(best) || (largest ? g > best : g < best)) {
        best = g;
        best_y = y;
      }
    }
    if (!std::isnan(best)) place_at(best_y);
    return best;
  };
  auto torso_place = [&](const Eigen::Vector3d& front, double behind) {
    return [&, behind](double y) {
      const Eigen::Vector3d inside(0.0, y, front.z() - behind);
      record(inside, Eigen::Vector3d::UnitY(), inside);
    };
  };

  auto measure = [&](Measurement measurement) -> double {
    switch (measurement) {
      case Measurement::kStature:
        return top - floor;
      case Measurement::kWeight:
        return EnclosedVolume(positions, triangles) * kBodyDensity;
      case Measurement::kBustGirth:
        return extreme_over({bust.y() - 0.04, bust.y() + 0.04}, true,
                            [&](double y) { return chest_girth(y, bust); },
                            torso_place(bust, 0.10));
      case Measurement::kUnderbustGirth:
        torso_place(underbust, 0.10)(underbust.y());
        return chest_girth(underbust.y(), underbust);
      case Measurement::kWaistGirth:
        return extreme_over({navel.y(), underbust.y()}, false,
                            [&](double y) { return torso_girth(y, navel); },
                            torso_place(navel, 0.05));
      case Measurement::kNavelWaistGirth:
        torso_place(navel, 0.05)(navel.y());
        return torso_girth(navel.y(), navel);
      case Measurement::kHipGirth:
        return extreme_over({crotch.y() + 0.01, crotch.y() + 0.6 * (navel.y() - crotch.y())},
                            true, [&](double y) { return torso_girth(y, crotch); },
                            torso_place(crotch, 0.05));
      case Measurement::kThighGirth: {
        // The left thigh: the largest loop left of the centre line (the hand hangs further out).
        auto thigh_at = [&](double y) -> std::pair<double, Eigen::Vector3d> {
          const PlaneSection section = horizontal(Eigen::Vector3d(0, y, 0));
          double best = std::numeric_limits<double>::quiet_NaN();
          double best_area = 0;
          Eigen::Vector3d centre = Eigen::Vector3d::Zero();
          for (const auto& loop : section.loops) {
            if (loop.size() < 3) continue;
            const Eigen::Vector2d centroid = Centroid(loop);
            const Eigen::Vector3d world =
                section.origin + centroid.x() * section.u + centroid.y() * section.v;
            if (world.x() <= 0 || world.x() > 0.25) continue;
            const double area = std::abs(SignedArea(loop));
            if (area > best_area) {
              best_area = area;
              best = ConvexHullPerimeter(loop);
              centre = world;
            }
          }
          return {best, centre};
        };
        return extreme_over({crotch.y() - 0.08, crotch.y() - 0.01}, true,
                            [&](double y) { return thigh_at(y).first; },
                            [&](double y) {
                              record(Eigen::Vector3d(0, y, 0), Eigen::Vector3d::UnitY(),
                                     thigh_at(y).second);
                            });
      }
      case Measurement::kUpperArmGirth: {
        // Midway from acromion to olecranon the plane also cuts the torso beside the arm: of
        // the loops near the landmarks' line, the arm's is the one furthest from the centre
        // line. On some bodies the plane there still passes through the armpit, where the mesh
        // joins arm and torso into one loop; the girth is then taken where the arm first
        // separates, up to 70% of the way to the olecranon.
        for (double along = 0.5; along <= 0.7 + 1e-9; along += 0.05) {
          const Eigen::Vector3d middle = acromion + along * (olecranon - acromion);
          const PlaneSection section =
              SectionMesh(positions, triangles, middle, olecranon - acromion);
          double best = std::numeric_limits<double>::quiet_NaN();
          double outermost = -std::numeric_limits<double>::infinity();
          for (const auto& loop : section.loops) {
            if (loop.size() < 3) continue;
            const Eigen::Vector2d c = Centroid(loop);
            const Eigen::Vector3d world = section.origin + c.x() * section.u + c.y() * section.v;
            if ((world - middle).norm() > kArmReach || world.x() <= outermost) continue;
            outermost = world.x();
            best = ConvexHullPerimeter(loop);
            record(middle, olecranon - acromion, world);
          }
          if (!std::isnan(best)) return best;
        }
        return std::numeric_limits<double>::quiet_NaN();
      }
      case Measurement::kNeckGirth: {
        const Eigen::Vector3d front = at(L::kNeckFront);
        const Eigen::Vector3d back = at(L::kNeckBack);
        const Eigen::Vector3d normal = Eigen::Vector3d::UnitX().cross(back - front);
        record(front, normal, (front + back) / 2);
        return GirthAround(SectionMesh(positions, triangles, front, normal), (front + back) / 2);
      }
      case Measurement::kInsideLeg:
        return crotch.y() - floor;
      case Measurement::kArmLength:
        return (olecranon - acromion).norm() + (wrist - olecranon).norm();
      case Measurement::kShoulderWidth:
        return (at(L::kRightAcromion) - acromion).norm();
    }
    return std::numeric_limits<double>::quiet_NaN();
  };

  BodyMeasurements m;
  m.fill(std::numeric_limits<double>::quiet_NaN());
  for (Measurement measurement : which) {
    place.reset();
    const double value = measure(measurement);
    if (!std::isfinite(value) || value <= 0) {
      return absl::InvalidArgumentError(
          absl::StrCat("the body's ", MeasurementName(measurement),
                       " cannot be taken: no section of the mesh encloses its landmark"));
    }
    m[static_cast<int>(measurement)] = value;
    if (places != nullptr) (*places)[static_cast<int>(measurement)] = place;
  }
  return m;
}

}  // namespace fitbase::body
