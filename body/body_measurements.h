#ifndef FITBASE_BODY_BODY_MEASUREMENTS_H_
#define FITBASE_BODY_BODY_MEASUREMENTS_H_

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"

namespace fitbase::body {

// The tailor's measurements fitbase takes on a body, after ISO 8559-1 (garment construction
// anthropometry) where it defines them; how each is taken on the mesh is stated below and in
// the README. Lengths and girths are meters, weight kilograms.
enum class Measurement {
  kStature = 0,      // Floor (lowest vertex) to the top of the head, vertical.
  kWeight,           // Enclosed volume times kBodyDensity.
  kBustGirth,        // Largest torso girth within 4 cm of the bust point's height (men: chest).
  kUnderbustGirth,   // Torso girth at the inframammary fold's height.
  kWaistGirth,       // Smallest torso girth between the navel and the underbust (natural waist).
  kHipGirth,         // Largest torso girth over the buttocks: crotch + 1 cm to 60% up to the navel.
  kThighGirth,       // Largest left-thigh girth from 8 cm to 1 cm below the crotch.
  kUpperArmGirth,    // Left arm, perpendicular to it, midway from acromion to olecranon.
  kNeckGirth,        // Below the laryngeal prominence, in the plane through the nape point.
  kInsideLeg,        // Crotch to floor, vertical.
  kArmLength,        // Left acromion over the olecranon to the wrist (ulnar styloid).
  kShoulderWidth,    // Between the two acromions, straight (biacromial breadth).
  kNavelWaistGirth,  // Torso girth at the navel: ANSUR II's "waist circumference (omphalion)".
};
inline constexpr int kMeasurementCount = 13;

// Whole-body density: tissue is 1,040 to 1,070 kg/m^3 with the lungs emptied, and the air in
// the lungs at rest (about 3 L) brings a whole body near 1,010.
inline constexpr double kBodyDensity = 1010.0;  // kg/m^3

// "stature", "weight", "bust_girth", ...: the names of files, JSON and the command line.
absl::string_view MeasurementName(Measurement measurement);
// INVALID_ARGUMENT naming `name` and listing the known names.
absl::StatusOr<Measurement> ParseMeasurement(absl::string_view name);
// True for weight (kg), false for the lengths and girths (m).
bool IsMass(Measurement measurement);
// The unit a person reads and types a measurement in: "kg" for weight, "cm" for the others.
absl::string_view TypedUnit(Measurement measurement);
// `value` (m, or kg for weight) in TypedUnit.
double InTypedUnit(Measurement measurement, double value);
std::span<const Measurement> AllMeasurements();

using BodyMeasurements = std::array<double, kMeasurementCount>;  // By Measurement index.

// Landmarks: hm08 body vertices (0..13379), found once on MakeHuman's default woman and man
// and checked on both; every body of that topology carries them.
struct BodyLandmarks {
  static constexpr int32_t kLeftBustPoint = 8454;       // Nipple, most forward on the breast.
  static constexpr int32_t kLeftUnderbust = 8540;       // Inframammary fold below the nipple.
  static constexpr int32_t kNavel = 4121;               // Omphalion, on the centre line.
  static constexpr int32_t kCrotch = 4372;              // Lowest centre-line point of the torso.
  static constexpr int32_t kLeftAcromion = 8069;        // Top of the shoulder's bony tip.
  static constexpr int32_t kRightAcromion = 1377;       // Its mirror image.
  static constexpr int32_t kLeftOlecranon = 9991;       // Point of the elbow.
  static constexpr int32_t kLeftWrist = 10182;          // Ulnar styloid, back of the wrist.
  static constexpr int32_t kNeckFront = 809;            // Just below the laryngeal prominence.
  static constexpr int32_t kNeckBack = 857;             // Nape, where that girth crosses it.
  static constexpr int32_t kLeftAnkle = 12836;          // Lateral malleolus, ankle's outer tip.
};

// The perimeter of the convex hull of `points` (any count; fewer than 2 give 0), the way a
// tape bridges hollows.
double ConvexHullPerimeter(std::span<const Eigen::Vector2d> points);

// The closed loops in which the plane through `point` with normal `normal` (need not be unit)
// cuts the triangle mesh (positions V x 3, triangles T x 3), each as its points in the plane's
// own 2D frame (u, v, both perpendicular to the normal). Loops are separated by mesh
// connectivity, so an arm's section is never merged with the torso's.
// Each loop point also names the mesh edge it lies on (vertices a, b; the point is
// a + t (b - a)), which ties a section of a deformed mesh to the same material points at rest.
struct SectionEdgePoint {
  int32_t a;
  int32_t b;
  double t;
};
struct PlaneSection {
  Eigen::Vector3d origin;
  Eigen::Vector3d u;
  Eigen::Vector3d v;
  std::vector<std::vector<Eigen::Vector2d>> loops;
  std::vector<std::vector<SectionEdgePoint>> edges;  // Parallel to loops.
  // Whether each loop closes; an open mesh's boundary ends a loop without closing it.
  std::vector<bool> closed;
};
PlaneSection SectionMesh(const core::Positions& positions, const core::Triangles& triangles,
                         const Eigen::Vector3d& point, const Eigen::Vector3d& normal);

// Where a girth was taken: the section plane (through `point`, with unit `normal`) and a point
// of that plane inside the measured loop (the loop's centroid for a limb).
struct GirthPlace {
  Eigen::Vector3d point;
  Eigen::Vector3d normal;
  Eigen::Vector3d inside;
};

// Whether the closed 2D polygon `loop` holds `p` (even-odd rule).
bool LoopContains(const std::vector<Eigen::Vector2d>& loop, const Eigen::Vector2d& p);
// The area a closed 2D polygon encloses (absolute, any winding).
double LoopArea(const std::vector<Eigen::Vector2d>& loop);

// The convex hull perimeter of the loop of `section` that encloses `inside` (a point of its
// plane), m, or NaN when no loop does; the largest such loop when several do.
double GirthAround(const PlaneSection& section, const Eigen::Vector3d& inside);

// The enclosed volume of a closed, outward-oriented triangle mesh (m^3 for meters).
double EnclosedVolume(const core::Positions& positions, const core::Triangles& triangles);

// Measures a body of topology makehuman-hm08-body: positions 13,380 x 3, meters, +Y up, +Z
// the front, standing on its lowest vertex; faces of that topology. INVALID_ARGUMENT for
// another vertex count, non-finite positions, or a body whose sections at a landmark find no
// loop there (a mesh that is not a body).
absl::StatusOr<BodyMeasurements> MeasureBody(const core::Mesh& body);

// The same with the faces already triangulated (what MeasureBody does first), taking only
// the measurements in `which` (the others are NaN): for callers that measure many bodies of
// one topology, a few measurements at a time.
// With `places`, also where each girth of `which` was taken (the others are left empty).
absl::StatusOr<BodyMeasurements> MeasureBody(
    const core::Positions& positions, const core::Triangles& triangles,
    std::span<const Measurement> which,
    std::array<std::optional<GirthPlace>, kMeasurementCount>* places = nullptr);

}  // namespace fitbase::body

#endif  // FITBASE_BODY_BODY_MEASUREMENTS_H_
