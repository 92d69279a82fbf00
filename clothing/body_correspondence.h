#ifndef FITBASE_CLOTHING_BODY_CORRESPONDENCE_H_
#define FITBASE_CLOTHING_BODY_CORRESPONDENCE_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "Eigen/Core"
#include "Eigen/StdVector"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/mesh.h"
#include "core/pca_basis.h"
#include "core/triangle_bvh.h"

namespace fitbase::clothing {

// The collision clean-up of a fast fit, in bounded time per fit (no search, but for the few
// deep pushes checked against the body as a whole mesh when the fit has one,
// PushOutOfBodyPoints):
//   - Vertices. Each garment vertex keeps up to K anchors: the body surface points it was
//     closest to in the example drapes (triangle and barycentric coordinates), with the
//     triangles' corners as a linear model in the avatar weights. At fit time the customer's
//     triangles are rebuilt from the weights and the anchor nearest the fitted vertex asks for
//     the vertex to lie `offset` out along that triangle's normal. Anchors from several examples
//     follow a vertex that slides from one body part's surface to another's.
//   - Triangles. Garment edges are 1 to 3 cm long, and between its vertices the body bulges
//     through a garment triangle. Each guard is a body vertex that lay under a garment
//     triangle (its closest point on the drape, within a reach) in the example drapes; at fit
//     time a guard whose point projects inside its triangle and lies closer than `offset` under
//     it asks for the triangle to rise there, shared among the corners by the point's
//     barycentric coordinates.
//   - Smoothness. The requests are met by a displacement field over the garment, not vertex by
//     vertex: requests are applied, then `smoothing_iterations` rounds of averaging the field
//     over each vertex's garment neighbours (Jacobi steps of the Laplacian, towards TailorNet's
//     Laplacian-preserving least squares), each pushed vertex keeping at least its own push,
//     and the requests once more; a push fades over the neighbours instead of leaving a dent
//     or a spike.
// Without guards and smoothing (bases built before them) only the vertices are pushed.
struct BodyCorrespondence {
  double offset = 0;                   // m.
  int anchors_per_vertex = 1;          // K.
  std::vector<int32_t> body_vertices;  // U avatar vertices the triangles use, ascending.
  Eigen::VectorXf body_mean;           // 3U, m.
  Eigen::MatrixXf body_components;     // 3U x N.
  // Rows v * K .. v * K + K - 1 are garment vertex v's anchors: the triangle's corners as rows
  // of body_vertices, and the barycentric coordinates of the anchor in it.
  Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> corners;
  Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> barycentric;
  // Guard g: the body vertex guard_body[g] (a row of body_vertices) under the garment triangle
  // guard_triangles.row(g) (garment vertex indices), its corners ordered so that
  // (b - a) x (c - a) points away from the body.
  std::vector<int32_t> guard_body;
  Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> guard_triangles;
  int smoothing_iterations = 0;  // 0: no smoothing.
  // The body under the garment: the avatar triangles whose corners are all body points, as
  // rows of body_vertices (R x 3, counter-clockwise from outside), which the clean-up's deep
  // pushes ask (PushOutOfBodyPoints). Empty, as in bases built before stop 50: none asked.
  core::Triangles body_triangles;
  // The garment's edges (derived from its faces, not stored): vertex v's neighbours are
  // neighbors[neighbor_offsets[v] .. neighbor_offsets[v + 1]), ascending. Empty: no smoothing.
  std::vector<int32_t> neighbor_offsets;
  std::vector<int32_t> neighbors;
  int64_t vertex_count() const { return corners.rows() / anchors_per_vertex; }
  int component_count() const { return static_cast<int>(body_components.cols()); }
};

// A configuration the garment was seen in: a drape (V x 3, m) and its body's avatar weights.
struct CorrespondenceExample {
  const core::Positions* garment = nullptr;
  Eigen::VectorXd weights;  // N, m.
};

// How far under a garment triangle (m) a body vertex of an example drape becomes a guard: fits
// err by about a centimetre, so a body point well under the drape can still reach the fit.
inline constexpr double kGuardReach = 0.02;
// Guards per body vertex: its most frequent triangles over the examples. A second one caught
// a little more skin (female garments, size M, 4 rounds of Jacobi smoothing: 0.80% of cloth
// pixels shown as skin against 0.85%) for twice the guards; the smoothing carries a push to
// the neighbouring triangles anyway.
inline constexpr int kGuardsPerBodyVertex = 1;
// Rounds of smoothing (Jacobi, over the whole garment). Each round costs some 3 ns per garment
// vertex (male_casualsuit01: 8.4k vertices, 6 neighbours each on average). Until stop 52 they
// were Gauss-Seidel sweeps over the vertices a push had reached, alternating direction; those
// were 0.006 mm closer to the drape on the women's four garments in M and showed the same
// skin, at 2.2 times the cost. 4 Gauss-Seidel rounds showed 0.05 points less skin (0.87% of
// cloth pixels against 0.92%) for a fifth more clean-up time.
inline constexpr int kSmoothingIterations = 2;
// More rounds than this are refused as a stored basis's value: the fit's cost grows with them.
inline constexpr int kMaxSmoothingIterations = 64;

// examples: the mean drape first (weights 0), then any others; avatar: the basis the weights
// refer to (D = 3 x body vertices); body_triangles: the avatar topology, counter-clockwise
// from outside; garment_triangles: T x 3 indices into the garment's V vertices, either
// orientation (empty: no guards and no smoothing, vertices pushed one by one); offset: m, > 0;
// anchors_per_vertex: K >= 1, the most frequent closest triangles over the examples (ties: the
// earlier example), padded by repeating the first. Guards take kGuardReach,
// kGuardsPerBodyVertex and smoothing kSmoothingIterations; the result's body_triangles, every
// avatar triangle whose corners are all body points. InvalidArgument for non-finite or
// mismatched input.
absl::StatusOr<BodyCorrespondence> BuildBodyCorrespondence(
    const std::vector<CorrespondenceExample>& examples, const core::PcaBasis& avatar,
    const core::Triangles& body_triangles, const core::Triangles& garment_triangles, double offset,
    int anchors_per_vertex);

// Fills correspondence's neighbour lists from the garment's triangles (V = vertex_count()).
// InvalidArgument for an index outside [0, V).
absl::Status SetGarmentNeighbors(const core::Triangles& garment_triangles,
                                 BodyCorrespondence& correspondence);

// Sizes, indices and values agree and are finite.
absl::Status ValidateBodyCorrespondence(const BodyCorrespondence& correspondence,
                                        int64_t garment_vertex_count, int component_count);

// One request of the clean-up: displacement d of corners `vertices` must satisfy
// sum_i weights[i] * d[vertices[i]] . normal >= amount (m).
struct ClearanceRequest {
  int32_t vertices[3];
  float weights[3];
  Eigen::Vector4f normal;  // Unit, w = 0.
  float amount;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

// A push deeper than this (m) behind the vertex's anchor plane is checked against the body
// under the garment (BodyCorrespondence::body_triangles). The plane goes on past the body part
// under the anchor: on heavy men a bib overall's straps, fitted on the front of the chest, lay
// 8 to 18 cm behind their anchors on the upper back, and the plane pushed them through the
// torso (stop 48). Shallower pushes are left to the plane, which needs no search.
inline constexpr double kDeepPush = 0.03;

// Working memory of PushOutOfBody, sized on first use, so a warm fit allocates nothing.
// Points are padded to 4 floats (w = 0) for aligned vector loads.
struct CleanupScratch {
  Eigen::VectorXf body;          // 3U, m: the body of the weights.
  Eigen::VectorXf own_body;      // 3U, m: a body given as a mesh (ClothingFitter::FitToBody).
  Eigen::VectorXf follow;        // 4V, m: FollowBody's field.
  Eigen::VectorXf follow_next;   // 4V, m: its next round.
  Eigen::VectorXf moved4;        // 4U, m: FollowBody's body less the body fitted for.
  std::vector<int32_t> anchor_rows;  // V: each vertex's anchor row (FollowBody's, or the nearest).
  Eigen::VectorXf body4;         // 4U, m.
  Eigen::VectorXf garment4;      // 4V, m: the fit before the clean-up.
  Eigen::VectorXf displacement;  // 4V, m; zero between fits.
  Eigen::VectorXf displacement_next;  // 4V, m: its next round.
  std::vector<ClearanceRequest, Eigen::aligned_allocator<ClearanceRequest>> requests;
  std::vector<int32_t> pushed;  // The requests' vertices, each once; capacity V.
  std::vector<uint8_t> marked;  // V: in `pushed`; zero between fits.
  // Per pushed vertex: its push (w = 0) and the push's squared length.
  std::vector<Eigen::Vector4f, Eigen::aligned_allocator<Eigen::Vector4f>> held;
  std::vector<float> held_squared;
  // The tree of the body under the garment, for the deep pushes: built on the first, refitted
  // on later fits' first (the topology kept), and current within one clean-up.
  std::optional<core::TriangleBvh> body_tree;
  core::Positions body_tree_positions;  // U x 3, m: the body points.
  bool body_tree_current = false;
  int64_t deep_checks = 0;  // Of the last clean-up: pushes checked against the body.
};

// The correspondence's U body points on the body of the weights (mean + components x
// weights, N): points, 3U floats (m), xyz interleaved.
void BodyPointsOfWeights(const BodyCorrespondence& correspondence,
                         const Eigen::VectorXf& weights, Eigen::VectorXf& points);

// The correspondence's U body points taken from a body mesh: avatar, 3B floats (m), xyz
// interleaved, in the avatar topology's vertex order; points, 3U floats (m). InvalidArgument
// for a count that is not 3B, a body with too few vertices for the correspondence, or a
// gathered coordinate that is not finite.
absl::Status GatherBodyPoints(const BodyCorrespondence& correspondence,
                              std::span<const float> avatar, Eigen::VectorXf& points);

// Rounds of smoothing of FollowBody's field. On the women's four garments in M (400 sampled
// drapes, 10 held-out women), the fit to the own mesh missed its drape by 3.22 mm without,
// 3.18 with 2 rounds, 3.17 with 4, and 3.16 with 8 or 16. Two: on 800 drapes and 30 women,
// 4 rounds were 0.006 mm closer (2.74 mm) and cost 55 us more on male_casualsuit01's 8.4k
// vertices, a tenth of the fit's budget.
inline constexpr int kFollowSmoothingIterations = 2;

// Carries a garment fitted for one body (fitted_for, 3U floats, m) onto another body of the
// same topology (body, 3U): each vertex moves by how far `body` lies out from `fitted_for`
// (inwards: negative) at the vertex's nearest anchor, along that anchor's triangle normal on
// `fitted_for`, then the field is averaged over the garment's neighbours
// (kFollowSmoothingIterations Jacobi rounds; none without neighbour lists). Only the normal
// part is carried: tangentially, cloth does not follow the skin millimetre by millimetre (on
// held-out women, the drape on the body of the weights carried this way came 11% closer to the
// drape on the own mesh; carried with the tangential part too, it came 2% further). positions:
// 3V floats (m), moved in place. Leaves each vertex's anchor row in scratch.anchor_rows, for
// the clean-up that follows. Costs about one pass of the clean-up's vertex loop and the rounds.
void FollowBody(const BodyCorrespondence& correspondence, const Eigen::VectorXf& fitted_for,
                const Eigen::VectorXf& body, CleanupScratch& scratch, float* positions);

// positions: 3V floats (m), xyz interleaved, moved in place; weights: N, checked by the
// caller; correspondence: validated. Clears the body of the weights (PushOutOfBodyPoints).
// Returns how many vertices moved. No iteration to convergence: the cost is bounded by V, K,
// G, U, N, the rounds and the neighbour count (each round of smoothing visits every vertex
// and edge once), plus, in a fit with deep pushes, one refit of the tree of the body under the
// garment and one search of it per deep push. InvalidArgument for weights so far outside any
// body that a body point overflows, found when a push is deep.
absl::StatusOr<int64_t> PushOutOfBody(const BodyCorrespondence& correspondence,
                                      const Eigen::VectorXf& weights, CleanupScratch& scratch,
                                      float* positions);

// As PushOutOfBody, clearing the body given by its U points (3U floats, m: from
// BodyPointsOfWeights or GatherBodyPoints). anchor_rows: empty (each vertex's nearest, found
// here into scratch.anchor_rows), or V rows of `corners`, the anchor each vertex is cleared
// against instead of its nearest (FollowBody's: it moved the vertex along that anchor's normal
// only, so the nearest is found once per fit, not twice; they may be scratch.anchor_rows).
// With the correspondence's body_triangles, a vertex more than kDeepPush behind its anchor's
// plane is asked of the body under the garment (its exact closest point there, signed):
//   - At a surface facing away from the anchor's side (normals at an obtuse angle), the plane
//     lies beyond the body, and its push would cross it: the vertex is cleared against that
//     surface instead, left where it is if `offset` or more outside it, else pushed out along
//     its normal to `offset`. Without this, male_worksuit01's straps, fitted on the front of
//     heavy men's chests, were pushed 16 to 33 cm through the torso (stop 48).
//   - Clear of the body by `offset` or more otherwise: pushed along the anchor's normal by
//     kDeepPush, no more. Nothing collides there; the push only pulls the vertex towards its
//     anchor's side, and is trusted as far as the plane pushes unasked. Unbounded, it flung
//     those straps 24 cm over a man's shoulders; not made at all, a crop top's hem fitted 2 cm
//     high on a full bust showed a band of skin where the drape has cloth (female_sportsuit01
//     S, 30 held-out women: 0.52% of the drape's cloth pixels against 0.35%; 0.47% bounded).
//   - Else (inside, or within `offset` of a surface on the anchor's side) the plane's push.
// Body parts no anchor lies on (a head above a pair of trousers) are not asked: the points
// carry no others, and the region's tree costs a fraction of the whole body's (on
// male_worksuit01 M, a fit from the weights with 58 deep pushes took 826 us with the whole
// body of the weights made from the avatar basis, 246 us with its region; 198 us at a body
// with none). The tree is built (or refitted) once per clean-up that has such a vertex, none
// otherwise. InvalidArgument for a body point under the garment that is not finite.
absl::StatusOr<int64_t> PushOutOfBodyPoints(const BodyCorrespondence& correspondence,
                                            const Eigen::VectorXf& body,
                                            std::span<const int32_t> anchor_rows,
                                            CleanupScratch& scratch, float* positions);

}  // namespace fitbase::clothing

#endif  // FITBASE_CLOTHING_BODY_CORRESPONDENCE_H_
