#ifndef FITBASE_WORKERS_CLOTH_SOLVER_H_
#define FITBASE_WORKERS_CLOTH_SOLVER_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "Eigen/Core"
#include "core/mesh.h"
#include "core/triangle_bvh.h"
#include "workers/cloth_model.h"

namespace fitbase::workers {

// Physical and numerical settings of the drape. Distances in meters, times in seconds.
struct ClothSettings {
  double step_seconds = 1.0 / 30.0;
  int substeps = 16;
  double gravity = 9.81;        // Along -y.
  double areal_density = 0.15;  // kg/m^2, a light woven fabric.
  // XPBD compliances (inverse stiffness), m/N: near-inextensible stretch, soft bending.
  double stretch_compliance = 1e-8;
  double bend_compliance = 2e-4;
  double anchor_compliance = 1e-6;
  // Share of the velocity removed per substep: quasi-static drapes want strong damping.
  double damping = 0.1;
  double collision_offset = 0.0025;
  double collision_search = 0.03;  // Penetrations deeper than this are not seen.
  double friction = 0.1;           // Share of tangential slip removed on contact.
};

// Extended position-based dynamics (Macklin, Mueller, Chentanez 2016) with small steps: one
// Gauss-Seidel sweep per substep over stretch, bend and anchor constraints in a fixed order,
// then body collisions, so a run is bitwise reproducible.
class ClothSolver {
 public:
  // `start` (V x 3, m) on the body `body`; rest lengths per model.edges and model.bends.
  // Anchors are bound to the body surface nearest them on `body`.
  ClothSolver(const ClothModel& model, const core::Positions& start, Eigen::VectorXd edge_rest,
              Eigen::VectorXd bend_rest, const core::TriangleBvh& body,
              const ClothSettings& settings);

  // Advances one step with the body as `body` now is (the caller refits it between steps).
  // Returns the largest vertex move of the step, meters.
  double Step(const core::TriangleBvh& body);

  // Pushes every vertex closer than the offset (or inside, up to `search` deep) out to the
  // offset along the body's pseudo-normal; returns how many moved.
  int ResolveCollisions(const core::TriangleBvh& body, double search);

  const core::Positions& positions() const { return positions_; }

 private:
  struct AnchorBinding {
    int32_t vertex;
    int32_t triangle;
    Eigen::Vector3d barycentric;
    double height_above;  // Vertex height minus the bound surface point's height, m.
  };

  void Substep(const core::TriangleBvh& body, double h);
  void SolvePairs(const std::vector<std::array<int32_t, 2>>& pairs, const Eigen::VectorXd& rest,
                  double alpha);
  void SolveAnchors(const core::TriangleBvh& body, double alpha);
  // Long-range attachments (Kim, Chentanez, Mueller 2012): no vertex may be farther from its
  // nearest anchor than their rest geodesic distance, which stops the sag-stretch that a few
  // Gauss-Seidel sweeps leave in a garment hanging from its waistband.
  void SolveTethers();
  void BuildTethers();
  // Garment triangles that body vertices may poke through (vertex-only collision lets
  // coarse triangles cut through a convex body between their corners): found once per step,
  // resolved every substep by SolvePokes.
  void FindPokes(const core::TriangleBvh& body);
  void SolvePokes(const core::TriangleBvh& body);
  void Collide(const core::TriangleBvh& body, double search, bool with_friction);

  const ClothModel& model_;
  ClothSettings settings_;
  Eigen::VectorXd edge_rest_;
  Eigen::VectorXd bend_rest_;
  std::vector<AnchorBinding> anchors_;
  struct Tether {
    int32_t vertex;
    int32_t anchor;
    double max_distance;  // Rest geodesic distance to the anchor, m.
  };
  std::vector<Tether> tethers_;
  std::optional<core::TriangleBvh> garment_bvh_;
  // The floor the body stands on (its lowest point), m: long hems rest on it instead of
  // swinging under the feet.
  double floor_ = 0;
  struct Poke {
    int32_t body_vertex;
    int32_t triangle;
    Eigen::Vector3d normal;  // The body vertex's outward normal.
  };
  std::vector<Poke> pokes_;
  core::Positions positions_;
  core::Positions previous_;
  core::Positions velocities_;
};

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_CLOTH_SOLVER_H_
