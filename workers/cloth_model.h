#ifndef FITBASE_WORKERS_CLOTH_MODEL_H_
#define FITBASE_WORKERS_CLOTH_MODEL_H_

#include <array>
#include <cstdint>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "body/body_skeleton.h"
#include "core/mesh.h"

namespace fitbase::workers {

// A boundary loop of a garment: a waistband, collar, cuff, hem or shoe opening.
struct Opening {
  std::vector<int32_t> vertices;  // Ascending.
  std::vector<int32_t> edges;     // Its boundary edges, ascending indices into ClothModel::edges.
  int32_t piece = 0;  // The connected piece of the garment it bounds, numbered from 0.
  double mean_height = 0;  // Of its vertices on the template, m.
  // The opening of its piece with the piece's highest vertex: a waistband, a collar, a bib
  // overall's straps or a shoe's opening.
  bool highest_of_piece = false;
};

// The constraint topology of a garment for the cloth solver, derived once from its faces.
// Vertex order is the garment's; constraints are stored in a fixed order so a solve visits
// them the same way every time.
struct ClothModel {
  core::Triangles triangles;  // Fan triangulation of the faces.
  // Stretch and shear: every distinct triangle edge (quad diagonals shear), i < j.
  std::vector<std::array<int32_t, 2>> edges;
  // Bending: for each edge shared by exactly two triangles, {edge end, edge end, the first
  // triangle's third vertex, the second triangle's third vertex} (see core::HingeAngle).
  std::vector<std::array<int32_t, 4>> hinges;
  // Per vertex: 1 / mass (kg^-1); 0 for vertices no face uses (they never move).
  Eigen::VectorXd inverse_masses;
  // Boundary loops, in the order of their lowest vertex.
  std::vector<Opening> openings;
};

// positions: the template, V x 3 (m); faces as given (polygons). areal_density: kg/m^2.
// Errors: a face index out of range, a degenerate model (no triangles).
absl::StatusOr<ClothModel> BuildClothModel(const core::Positions& positions,
                                           const core::PolygonFaces& faces,
                                           double areal_density);

// The openings that hold a garment up on the body, and its declared cuffs.
struct Supports {
  // Ascending indices into ClothModel::edges: the boundary edges of waistbands, which grip
  // the body as an elastic waistband does and carry ClothSettings::waistband_grip.
  std::vector<int32_t> waistband_edges;
  // Ascending indices into ClothModel::openings: collars, held at their height on the neck.
  std::vector<int32_t> collars;
  // Ascending indices into ClothModel::openings: top edges that go round the neck over the
  // shoulders but reach below the underbust (a bib overall's straps, bib and back), held at
  // their height as collars are. Not a collar: the neck's figures would average in the bib.
  std::vector<int32_t> straps;
  // Ascending indices into ClothModel::openings: elastic cuffs round the wrists or ankles
  // (FindCuffs), whose boundary edges carry a waistband's elastic. Only a garment declared with
  // them has any. Not anchored: held where they sit on the limb, as every vertex is, by the tie
  // to the skin point they started over, and by friction with ClothSettings::cuff_friction.
  // Anchored as a collar is (ClothSettings::anchor_stiffness; tried with a stiffer elastic than
  // now), the cuffs of a size too short for a tall body pulled its waistband 2.7 cm down the
  // rise (2.0 allowed), on seven of the 12 garments; held by the ties alone, 1.8 (1.7 with this
  // elastic, as without cuffs).
  std::vector<int32_t> cuffs;

  // Whether `opening` (of the garment these are the supports of) is a waistband.
  bool IsWaistband(const Opening& opening) const;
  // Whether the garment's opening with this index is a collar.
  bool IsCollar(int32_t opening) const;
  // Whether the garment's opening with this index is a strap.
  bool IsStrap(int32_t opening) const;
};

// The supports of a garment whose template `garment` (V x 3, m) sits on `mean_body` (the
// 13,380 x 3 body avatar it was fitted to, m). A support is the highest opening of its piece
// and rings the body: seen from above, it goes round the body's vertical axis. Between the
// crotch and the underbust, round the torso's (through the crotch), it is a waistband:
// trousers and skirts. Above the underbust, round the neck's (between the neck girth's
// landmarks), it is a collar if it stays above the underbust, else straps; a top hangs from
// the shoulders under either. An open jacket's front edge, which runs down from the neck and
// back round the hem, a button, a buckle's hole and a separate collar open at the front ring
// nothing; neither do shoes, below. INVALID_ARGUMENT for a body of another vertex count or a
// garment of another vertex count than the model's.
absl::StatusOr<Supports> FindSupports(const ClothModel& model, const core::Positions& garment,
                                      const core::Positions& mean_body);

// Which openings a garment's maker declares elastic cuffs (v1::ElasticCuffs).
struct CuffDeclaration {
  bool sleeves = false;
  bool legs = false;
};

// The cuffs `declared` of a garment whose template `garment` (V x 3, m; regions: the body
// region each vertex covers) sits on `mean_body` (the 13,380 x 3 body avatar it was fitted
// to, m; its triangles). A cuff is an opening that is not its piece's highest, most of whose
// vertices cover the arms (a sleeve's end) or the legs and feet with the mean of its vertices
// below the crotch (a leg's end), and that rings one limb: the body's section in the
// opening's plane has a loop round that mean (a skirt's hem, round both legs, has it between
// them). Ascending indices into model.openings; none when nothing is declared.
// INVALID_ARGUMENT for a body of another vertex count, or regions or a garment of another
// vertex count than the model's.
absl::StatusOr<std::vector<int32_t>> FindCuffs(const ClothModel& model,
                                               const core::Positions& garment,
                                               const std::vector<body::BodyRegion>& regions,
                                               const core::Positions& mean_body,
                                               const core::Triangles& body_triangles,
                                               CuffDeclaration declared);

// Current bending angles of `hinges` for `positions` (rad; 0 for a degenerate hinge).
Eigen::VectorXd HingeAngles(const core::Positions& positions,
                            const std::vector<std::array<int32_t, 4>>& hinges);

// Current lengths of `pairs` for `positions`.
Eigen::VectorXd PairLengths(const core::Positions& positions,
                            const std::vector<std::array<int32_t, 2>>& pairs);

// Areas of `model.triangles` (T) whose sides have the rest lengths `edge_rest` (per
// model.edges, m), by Heron's formula, m^2: a sized garment's triangles at rest. 0 for a
// triangle whose rest lengths do not close.
Eigen::VectorXd TriangleRestAreas(const ClothModel& model, const Eigen::VectorXd& edge_rest);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_CLOTH_MODEL_H_
