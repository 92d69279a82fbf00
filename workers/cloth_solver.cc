#include "workers/cloth_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "Eigen/Geometry"
#include "Eigen/SparseCore"
#include "absl/strings/str_cat.h"
#include "body/body_measurements.h"
#include "body/body_model.h"
#include "core/dihedral_angle.h"
#include "core/mesh.h"
#include "workers/fit_metrics.h"

namespace fitbase::workers {
namespace {

// How near a body vertex the body under a garment triangle must be for the triangle to be
// over that vertex: about the body's edge length.
constexpr double kOwnSurfaceRadius = 0.02;
// Body vertices this close to a garment triangle when the body comes to rest are checked
// against it for the rest of the drape.
constexpr double kPokeSearch = 0.01;
// How far a garment triangle must stay above a body vertex under it, m. Less than the
// collision offset: between its corners (which keep the offset) a flat triangle over a convex
// body sits lower, and asking more of it fights the corners' contacts.
constexpr double kPokeClearance = 0.0005;
// How far ClearTriangles lifts a garment triangle above a body vertex under it, m: enough that
// no body edge between the vertices shows through. Asked of the pokes during the drape, as much
// put the shirt front of male_casualsuit03 in and out of contact between nearby bodies (250
// kinks, second difference p99 2.4 mm against 1.1 at 0.1 sigma); asked once at the end, where it
// meets only triangles the penalty left lower, it kept 1.1 mm.
constexpr double kFinalClearance = 0.0015;
// Cloth is over a body vertex when the way to it is at least this much along the vertex's
// normal (cos 60 degrees); beside a hem it runs along the skin.
constexpr double kOverShare = 0.5;
// The longest vertex move of one Newton iteration, as a share of the collision search.
constexpr double kMaxMoveShareOfSearch = 0.5;
// Far above the rounding of a distance between points a few meters from the origin, m.
constexpr double kClearanceRounding = 1e-9;
// Armijo line search: sufficient decrease, and how often the step may be halved.
constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 12;
// With friction, the slip (m) at which a vertex's hold reaches mu times its normal force: a
// stiff spring for static friction, which a millimetre keeps below the garment's edge lengths
// and above the Newton tolerance.
constexpr double kStaticSlip = 1e-3;
// A push out of the body may halve its lift this often to fit between the sides of a crease,
// or double it this often to leave a crease whose sides touch, along it.
constexpr int kMaxPushHalvings = 5;
constexpr int kMaxPushDoublings = 3;
// |n1 + n2| of a crease's two side normals below which the sides face each other squarely and
// no direction leads out of it.
constexpr double kMinCreaseOpening = 0.05;

// Gauss-Newton Hessian block of a spring: exact along the spring, and across it only while
// stretched (a compressed spring's negative transverse stiffness is the buckling it should
// be free to do, and would make the system indefinite).
Eigen::Matrix3d SpringBlock(const Eigen::Vector3d& d, double length, double rest, double k) {
  if (length < 1e-12) return k * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d u = d / length;
  const Eigen::Matrix3d along = u * u.transpose();
  return k * (along + std::max(0.0, 1.0 - rest / length) * (Eigen::Matrix3d::Identity() - along));
}

// The crotch-to-navel height of an avatar body (13,380 x 3, m); 0 for another body, which has
// no such landmarks.
double RiseOf(const core::Positions& body) {
  return body.rows() == body::kBodyVertexCount ? Rise(body) : 0;
}

}  // namespace

absl::Status CheckFriction(double mu, absl::string_view name) {
  if (!std::isfinite(mu) || mu < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(name, " = ", mu, " must be finite and not negative"));
  }
  if (mu > kMaxFriction) {
    return absl::InvalidArgumentError(absl::StrCat(name, " = ", mu, " is over ", kMaxFriction));
  }
  return absl::OkStatus();
}

absl::Status CheckSkinTie(double tie, absl::string_view name) {
  if (!std::isfinite(tie) || tie < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(name, " = ", tie, " must be finite and not negative (N/m per kg)"));
  }
  if (tie > kMaxSkinTie) {
    return absl::InvalidArgumentError(
        absl::StrCat(name, " = ", tie, " is over ", kMaxSkinTie, " N/m per kg"));
  }
  return absl::OkStatus();
}

absl::Status CheckTightTies(const ClothSettings& settings) {
  const double factor = settings.tight_tie_factor;
  if (!std::isfinite(factor) || factor < 1 || factor > kMaxTightTieFactor) {
    return absl::InvalidArgumentError(
        absl::StrCat("tight_tie_factor = ", factor, " must be in [1, ", kMaxTightTieFactor, "]"));
  }
  for (const auto& [name, ratio] : {std::pair{"tight_girth_from", settings.tight_girth_from},
                                    std::pair{"tight_girth_full", settings.tight_girth_full}}) {
    if (!std::isfinite(ratio) || ratio < 0.5 || ratio > 2) {
      return absl::InvalidArgumentError(
          absl::StrCat(name, " = ", ratio, " must be a carried girth ratio in [0.5, 2]"));
    }
  }
  if (settings.tight_girth_from > settings.tight_girth_full) {
    return absl::InvalidArgumentError(
        absl::StrCat("tight_girth_from = ", settings.tight_girth_from,
                     " is over tight_girth_full = ", settings.tight_girth_full));
  }
  return absl::OkStatus();
}

Eigen::Vector3d ClothSolver::OnSkin(const core::TriangleBvh& body, const SkinPoint& skin) {
  const auto tri = body.triangles().row(skin.triangle);
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    point += skin.barycentric(k) * body.positions().row(tri(k)).transpose();
  }
  return point;
}

double ClothSolver::CarriedGirthRatio(const core::Positions& body,
                                      const core::Triangles& triangles) const {
  core::Positions carried = positions_;
  for (const SkinTie& tie : ties_) {
    Eigen::Vector3d point = tie.offset;
    for (int k = 0; k < 3; ++k) {
      point += tie.skin.barycentric(k) * body.row(triangles(tie.skin.triangle, k)).transpose();
    }
    carried.row(tie.vertex) = point.transpose();
  }
  double girth = 0;
  double rest_girth = 0;
  for (size_t e = 0; e < model_.edges.size(); ++e) {
    const auto [i, j] = model_.edges[e];
    const Eigen::Index index = static_cast<Eigen::Index>(e);
    girth += edge_across_(index) * (carried.row(i) - carried.row(j)).norm();
    rest_girth += edge_across_(index) * edge_rest_(index);
  }
  return rest_girth > 0 ? girth / rest_girth : 1.0;
}

double TightTieFactor(const ClothSettings& settings, double girth_ratio) {
  const double span = settings.tight_girth_full - settings.tight_girth_from;
  const double u = span > 0 ? std::clamp((girth_ratio - settings.tight_girth_from) / span, 0.0, 1.0)
                            : (girth_ratio >= settings.tight_girth_full ? 1.0 : 0.0);
  return std::pow(settings.tight_tie_factor, u * u * (3 - 2 * u));
}

void ClothSolver::HoldAnchors(const core::TriangleBvh& body) {
  // A band's anchors keep their heights over their skin points, and the band as a whole is
  // shifted to keep its mean place on the rise. Held on the rise vertex by vertex, a band
  // ignored how the skin under it moves (the belly's against the back's) and fought the
  // stiction of the cloth below it: female_casualsuit02's shorts slid 4 mm sideways between
  // bodies 0.1 sigma apart (second difference p99 5.0 mm; 0.76 mm shifted as a whole).
  anchor_over_skin_.resize(anchors_.size());
  band_shifts_.assign(band_shares_.size(), 0.0);
  std::vector<int> counts(band_shares_.size(), 0);
  for (size_t i = 0; i < anchors_.size(); ++i) {
    const AnchorBinding& a = anchors_[i];
    anchor_over_skin_[i] = OnSkin(body, a.skin).y() + a.height_above;
    if (a.band < 0) continue;
    band_shifts_[a.band] -= anchor_over_skin_[i];
    ++counts[a.band];
  }
  const core::Positions& p = body.positions();
  for (size_t b = 0; b < band_shifts_.size(); ++b) {
    if (counts[b] == 0) continue;
    band_shifts_[b] = band_shifts_[b] / counts[b] + p(body::BodyLandmarks::kCrotch, 1) +
                      band_shares_[b] * RiseOf(p);
  }
  tie_holds_.resize(ties_.size());
  for (size_t i = 0; i < ties_.size(); ++i) {
    const SkinTie& tie = ties_[i];
    tie_holds_[i].normal =
        core::TriangleCross(p, body.triangles(), tie.skin.triangle).normalized();
    tie_holds_[i].target = OnSkin(body, tie.skin) + tie.offset;
  }
}

// Where the 3 x 3 blocks the solver writes sit in the values the factorisation takes: one block
// per vertex, and one per pair of vertices that share an edge or a hinge (a contact between a
// body vertex and a garment triangle couples only the triangle's corners, which share edges).
// The blocks of every edge, hinge and triangle are looked up once, here: looked up per
// evaluation (a binary search per column) they were most of the bending's time.
class ClothSolver::HessianPattern {
 public:
  // A block and whether the caller's (i, j) is its transpose.
  struct Ref {
    int32_t block;
    bool transposed;
  };

  // Builds the lower triangle's pattern and has `cholesky` analyse it.
  HessianPattern(const ClothModel& model, SparseCholesky* cholesky)
      : vertex_count_(static_cast<int32_t>(model.inverse_masses.size())) {
    for (const auto& [i, j] : model.edges) pairs_.push_back({std::max(i, j), std::min(i, j)});
    // A hinge's other pairs are triangle edges already.
    for (const auto& h : model.hinges) {
      pairs_.push_back({std::max(h[2], h[3]), std::min(h[2], h[3])});
    }
    std::sort(pairs_.begin(), pairs_.end());
    pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
    std::vector<Eigen::Triplet<double>> entries;
    auto add_block = [&](int32_t i, int32_t j) {
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) entries.emplace_back(3 * i + a, 3 * j + b, 0.0);
    };
    for (int32_t v = 0; v < vertex_count_; ++v) add_block(v, v);
    for (const auto& [i, j] : pairs_) add_block(i, j);
    Eigen::SparseMatrix<double> pattern(3 * vertex_count_, 3 * vertex_count_);
    pattern.setFromTriplets(entries.begin(), entries.end());
    pattern.makeCompressed();
    const std::vector<int>& slots = cholesky->AnalyzePattern(pattern);
    value_count_ = cholesky->ValueCount();
    // Entry (a, b) of block (i, j): in the column 3j + b, at row 3i + a.
    auto slot = [&](int32_t i, int32_t j, int a, int b) {
      const int column = 3 * j + b;
      const int* begin = pattern.innerIndexPtr() + pattern.outerIndexPtr()[column];
      const int* end = pattern.innerIndexPtr() + pattern.outerIndexPtr()[column + 1];
      return slots[std::lower_bound(begin, end, 3 * i + a) - pattern.innerIndexPtr()];
    };
    blocks_.resize(static_cast<size_t>(vertex_count_) + pairs_.size());
    for (size_t k = 0; k < blocks_.size(); ++k) {
      const auto [i, j] = k < static_cast<size_t>(vertex_count_)
                              ? std::array<int32_t, 2>{static_cast<int32_t>(k),
                                                       static_cast<int32_t>(k)}
                              : pairs_[k - vertex_count_];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) blocks_[k][3 * a + b] = slot(i, j, a, b);
    }
    for (const auto& [i, j] : model.edges) edges_.push_back(Find(i, j));
    for (const auto& v : model.hinges) {
      std::array<Ref, 10>& refs = hinges_.emplace_back();
      int r = 0;
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b <= a; ++b) refs[r++] = Find(v[a], v[b]);
    }
    for (Eigen::Index t = 0; t < model.triangles.rows(); ++t) {
      std::array<Ref, 6>& refs = triangles_.emplace_back();
      const auto tri = model.triangles.row(t);
      int r = 0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b <= a; ++b) refs[r++] = Find(tri(a), tri(b));
    }
  }

  // The number of values, all blocks' entries.
  int ValueCount() const { return value_count_; }

  // Adds `block` at block row i, column j (and so its transpose at j, i), found by `ref`.
  void Add(Ref ref, const Eigen::Matrix3d& block, Eigen::VectorXd& values) const {
    const std::array<int, 9>& at = blocks_[ref.block];
    if (ref.block < vertex_count_) {
      // A vertex's own block is symmetric; the factorisation reads its lower triangle.
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b <= a; ++b) values(at[3 * a + b]) += block(a, b);
      return;
    }
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        values(at[3 * a + b]) += ref.transposed ? block(b, a) : block(a, b);
      }
  }
  void AddVertex(int32_t v, const Eigen::Matrix3d& block, Eigen::VectorXd& values) const {
    Add(Ref{v, false}, block, values);
  }

  // The block of model edge e's ends (i, j), as the edge lists them.
  Ref Edge(size_t e) const { return edges_[e]; }
  // The blocks of hinge h's pairs (a, b), b <= a, in that order, a and b index its vertices.
  const std::array<Ref, 10>& Hinge(size_t h) const { return hinges_[h]; }
  // The same for triangle t's corners.
  const std::array<Ref, 6>& Triangle(Eigen::Index t) const { return triangles_[t]; }

 private:
  Ref Find(int32_t i, int32_t j) const {
    if (i == j) return Ref{i, false};
    const std::array<int32_t, 2> key{std::max(i, j), std::min(i, j)};
    const auto at = std::lower_bound(pairs_.begin(), pairs_.end(), key);
    return Ref{vertex_count_ + static_cast<int32_t>(at - pairs_.begin()), i < j};
  }

  int32_t vertex_count_;
  int value_count_ = 0;
  std::vector<std::array<int32_t, 2>> pairs_;  // (row, column) vertex pairs, row > column.
  std::vector<std::array<int, 9>> blocks_;     // Per vertex, then per pair: entry a, b at 3a + b.
  std::vector<Ref> edges_;
  std::vector<std::array<Ref, 10>> hinges_;
  std::vector<std::array<Ref, 6>> triangles_;
};

ClothSettings WithoutSupports(ClothSettings settings) {
  settings.waistband_stiffness = 0;
  settings.anchor_stiffness = kUnsupportedAnchorStiffness;
  settings.waistband_anchor_stiffness = kUnsupportedAnchorStiffness;
  settings.waistband_on_rise = false;
  return settings;
}

ClothSolver::ClothSolver(const ClothModel& model, const core::Positions& start,
                         Eigen::VectorXd edge_rest, Eigen::VectorXd hinge_rest,
                         const Supports& supports, const core::TriangleBvh& body,
                         const ClothSettings& settings)
    : model_(model),
      settings_(settings),
      edge_rest_(std::move(edge_rest)),
      hinge_rest_(std::move(hinge_rest)),
      triangle_rest_areas_(TriangleRestAreas(model, edge_rest_)),
      nearest_triangles_(static_cast<size_t>(start.rows()), -1),
      clearances_(Eigen::VectorXd::Constant(start.rows(),
                                            -std::numeric_limits<double>::infinity())),
      positions_(start),
      step_start_(start),
      cholesky_(settings.factorization) {
  masses_ = Eigen::VectorXd::Zero(model.inverse_masses.size());
  for (Eigen::Index v = 0; v < masses_.size(); ++v) {
    if (model.inverse_masses(v) > 0) masses_(v) = 1.0 / model.inverse_masses(v);
  }
  std::vector<int32_t> tie_of(static_cast<size_t>(start.rows()), -1);
  for (Eigen::Index v = 0; v < start.rows(); ++v) {
    if (masses_(v) == 0) continue;
    const core::SurfacePoint hit = body.Closest(start.row(v).transpose(), 1.0);
    if (!hit.found) continue;
    tie_of[v] = static_cast<int32_t>(ties_.size());
    ties_.push_back({static_cast<int32_t>(v), {hit.triangle, hit.barycentric},
                     start.row(v).transpose() - hit.point});
  }
  tie_mu_.assign(ties_.size(), settings.friction);
  if (settings.cuff_friction > 0) {
    for (int32_t cuff : supports.cuffs) {
      for (int32_t v : model.openings[cuff].vertices) {
        if (tie_of[v] < 0) continue;
        tie_mu_[tie_of[v]] = std::max(settings.friction, settings.cuff_friction);
      }
    }
  }
  friction_ = std::any_of(tie_mu_.begin(), tie_mu_.end(), [](double mu) { return mu > 0; });
  elastic_edge_.assign(model.edges.size(), false);
  if (settings.waistband_stiffness > 0) {
    for (int32_t e : supports.waistband_edges) elastic_edge_[e] = true;
    for (int32_t cuff : supports.cuffs) {
      for (int32_t e : model.openings[cuff].edges) elastic_edge_[e] = true;
    }
  }
  const double rise = RiseOf(body.positions());
  for (size_t o = 0; o < model.openings.size(); ++o) {
    const Opening& opening = model.openings[o];
    if (!opening.highest_of_piece) continue;
    // Openings that ring nothing (an open front, a button) are held as every top opening was
    // before the supports.
    double stiffness = kUnsupportedAnchorStiffness;
    const int32_t index = static_cast<int32_t>(o);
    if (supports.IsCollar(index) || supports.IsStrap(index)) {
      stiffness = settings.anchor_stiffness;
    } else if (supports.IsWaistband(opening)) {
      stiffness = settings.waistband_anchor_stiffness;
    }
    int32_t band = -1;
    if (settings.waistband_on_rise && supports.IsWaistband(opening) && rise > 0) {
      band = static_cast<int32_t>(band_shares_.size());
      band_shares_.push_back(0);
    }
    int anchored = 0;
    for (int32_t v : opening.vertices) {
      if (tie_of[v] < 0) continue;
      const SkinTie& tie = ties_[tie_of[v]];
      anchors_.push_back({v, tie.skin, tie.offset.y(), stiffness, band});
      if (band >= 0) band_shares_[band] += start(v, 1);
      ++anchored;
    }
    if (band >= 0) {
      const double crotch = body.positions()(body::BodyLandmarks::kCrotch, 1);
      band_shares_[band] = anchored > 0 ? (band_shares_[band] / anchored - crotch) / rise : 0;
    }
  }
  edge_across_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.edges.size()));
  for (size_t e = 0; e < model.edges.size(); ++e) {
    const Eigen::Vector3d d = start.row(model.edges[e][0]) - start.row(model.edges[e][1]);
    const double length = d.norm();
    // Welds (two coincident seam vertices) have no direction.
    if (length > 0)
      edge_across_(static_cast<Eigen::Index>(e)) = 1 - d.y() * d.y() / (length * length);
  }
  hinge_weights_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.hinges.size()));
  for (size_t h = 0; h < model.hinges.size(); ++h) {
    const auto& v = model.hinges[h];
    const Eigen::Vector3d x0 = start.row(v[0]), x1 = start.row(v[1]);
    const Eigen::Vector3d e = x1 - x0;
    const double areas = 0.5 * (e.cross(Eigen::Vector3d(start.row(v[2])) - x0).norm() +
                                e.cross(Eigen::Vector3d(start.row(v[3])) - x0).norm());
    if (areas > 0) {
      hinge_weights_(static_cast<Eigen::Index>(h)) =
          settings.bending_rigidity * 3 * e.squaredNorm() / areas;
    }
  }
  // The model's triangles and the start positions were validated when the model was built.
  garment_bvh_.emplace(*core::TriangleBvh::Build(positions_, model_.triangles));
  pattern_ = std::make_unique<HessianPattern>(model_, &cholesky_);
  last_body_ = body.positions();
  if (friction_) SlipTies(body);
}

ClothSolver::~ClothSolver() = default;

double ClothSolver::Step(const core::TriangleBvh& body) {
  step_start_ = positions_;
  const bool body_moved =
      body.positions().rows() != last_body_.rows() || body.positions() != last_body_;
  if (body_moved) last_body_ = body.positions();
  HoldAnchors(body);
  // Pokes are found once the body has come to rest (a step on the previous step's body), and
  // kept: a contact set found anew at every step of a moving body makes the path, and so the
  // result, depend on the step count.
  if (body_moved || !stepped_) {
    pokes_.clear();
    pokes_found_ = false;
  } else if (!pokes_found_) {
    pokes_ = FindPokes(body);
    pokes_found_ = true;
  }
  stepped_ = true;
  floor_ = body.positions().col(1).minCoeff();
  clearances_ = Eigen::VectorXd::Constant(positions_.rows(),
                                          -std::numeric_limits<double>::infinity());
  const int iterations = body_moved && !friction_ ? std::min(settings_.path_newton_iterations,
                                                             settings_.newton_iterations)
                                                  : settings_.newton_iterations;
  for (int i = 0; i < iterations; ++i) {
    if (!(NewtonIteration(body) > settings_.newton_tolerance)) break;
  }
  if (friction_) SlipTies(body);
  return (positions_ - step_start_).rowwise().norm().maxCoeff();
}

void ClothSolver::SlipTies(const core::TriangleBvh& body) {
  // At construction there is no step yet, and the ties are where the vertices are.
  if (!tie_normal_forces_.empty()) {
    for (size_t i = 0; i < ties_.size(); ++i) {
      if (tie_mu_[i] == 0) continue;
      SkinTie& tie = ties_[i];
      const Eigen::Vector3d& normal = tie_holds_[i].normal;
      const Eigen::Vector3d slip = (Eigen::Matrix3d::Identity() - normal * normal.transpose()) *
                                   (positions_.row(tie.vertex).transpose() - tie_holds_[i].target);
      const double s = slip.norm();
      if (s <= kStaticSlip) continue;
      const Eigen::Vector3d carried = (s - kStaticSlip) / s * slip;
      const core::SurfacePoint hit = body.Closest(OnSkin(body, tie.skin) + carried,
                                                  settings_.collision_search, tie.skin.triangle);
      // Carried farther than the search from the skin (a fold pulled off a concave crease),
      // the hold stays on its triangle.
      const SkinPoint skin = hit.found ? SkinPoint{hit.triangle, hit.barycentric} : tie.skin;
      const Eigen::Vector3d target = tie_holds_[i].target + carried;
      tie.skin = skin;
      tie.offset = target - OnSkin(body, skin);
      tie_holds_[i] = {
          target,
          core::TriangleCross(body.positions(), body.triangles(), skin.triangle).normalized()};
    }
  }
  Evaluation contact;
  contact.gradient = Eigen::VectorXd::Zero(3 * positions_.rows());
  contact.hessian = Eigen::VectorXd::Zero(pattern_->ValueCount());
  AddContacts(positions_, body, /*derivatives=*/true, &contact);
  tie_normal_forces_.resize(ties_.size());
  for (size_t i = 0; i < ties_.size(); ++i) {
    tie_normal_forces_[i] = contact.gradient.segment<3>(3 * ties_[i].vertex).norm();
  }
}

double ClothSolver::NewtonIteration(const core::TriangleBvh& body) {
  Evaluation here;
  Evaluate(positions_, body, /*derivatives=*/true, &here);
  nearest_triangles_ = std::move(here.nearest_triangles);
  clearances_ = std::move(here.clearances);
  if (!cholesky_.Factorize(here.hessian)) return 0;
  const Eigen::VectorXd direction = cholesky_.Solve(-here.gradient);
  const double slope = here.gradient.dot(direction);
  if (!(slope < 0)) return 0;
  const Eigen::Map<const core::Positions> delta(direction.data(), positions_.rows(), 3);
  // Contact is seen only within the collision search, so a Newton step that moved a vertex
  // farther could carry it through the body unseen (a waistband's elastic, before its contact
  // pushes back, would pull the band through the waist).
  const double longest = delta.rowwise().norm().maxCoeff();
  double alpha = std::min(1.0, kMaxMoveShareOfSearch * settings_.collision_search / longest);
  for (int halving = 0; halving <= kMaxHalvings; ++halving, alpha *= 0.5) {
    const core::Positions trial = positions_ + alpha * delta;
    Evaluation there;
    Evaluate(trial, body, /*derivatives=*/false, &there);
    if (there.energy <= here.energy + kArmijo * alpha * slope) {
      positions_ = trial;
      nearest_triangles_ = std::move(there.nearest_triangles);
      clearances_ = std::move(there.clearances);
      return alpha * delta.rowwise().norm().maxCoeff();
    }
  }
  return 0;
}

void ClothSolver::Evaluate(const core::Positions& x, const core::TriangleBvh& body,
                           bool derivatives, Evaluation* out) const {
  const Eigen::Index n = x.rows();
  out->energy = 0;
  if (derivatives) {
    out->gradient = Eigen::VectorXd::Zero(3 * n);
    out->hessian = Eigen::VectorXd::Zero(pattern_->ValueCount());
  }
  const double inertia = 1.0 / (settings_.step_seconds * settings_.step_seconds);
  for (Eigen::Index v = 0; v < n; ++v) {
    const double m = masses_(v);
    if (m == 0) {
      // Unused vertices stay where they are: a unit diagonal and no force.
      if (derivatives) pattern_->AddVertex(v, Eigen::Matrix3d::Identity(), out->hessian);
      continue;
    }
    const Eigen::RowVector3d offset = x.row(v) - step_start_.row(v);
    out->energy += 0.5 * m * inertia * offset.squaredNorm() + m * settings_.gravity * x(v, 1);
    if (!derivatives) continue;
    out->gradient.segment<3>(3 * v) += m * inertia * offset.transpose();
    out->gradient(3 * v + 1) += m * settings_.gravity;
    pattern_->AddVertex(v, m * inertia * Eigen::Matrix3d::Identity(), out->hessian);
  }
  AddSprings(x, derivatives, out);
  AddBending(x, derivatives, out);
  AddAreaFloor(x, derivatives, out);
  for (size_t i = 0; i < anchors_.size(); ++i) {
    const AnchorBinding& a = anchors_[i];
    const double c =
        x(a.vertex, 1) - anchor_over_skin_[i] - (a.band >= 0 ? band_shifts_[a.band] : 0.0);
    // A size too small holds its band and collars at their height as much more firmly as its
    // ties, or the ties of a long leg would drag the band down it.
    const double stiffness = a.stiffness * tie_factor_;
    out->energy += 0.5 * stiffness * c * c;
    if (!derivatives) continue;
    out->gradient(3 * a.vertex + 1) += stiffness * c;
    Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
    block(1, 1) = stiffness;
    pattern_->AddVertex(a.vertex, block, out->hessian);
  }
  // The stiction holds every vertex unless friction replaces it everywhere; a cuff's friction
  // adds to it, so a cuff off the skin is still held as the rest of the cloth is.
  const bool stiction = settings_.friction == 0;
  for (size_t i = 0; i < ties_.size(); ++i) {
    const SkinTie& tie = ties_[i];
    const bool friction = tie_mu_[i] > 0 && tie_normal_forces_[i] > 0;
    if (!stiction && !friction) continue;
    const Eigen::Vector3d& normal = tie_holds_[i].normal;
    const Eigen::Matrix3d tangential = Eigen::Matrix3d::Identity() - normal * normal.transpose();
    const Eigen::Vector3d slip =
        tangential * (x.row(tie.vertex).transpose() - tie_holds_[i].target);
    const double s = slip.norm();
    if (stiction) {
      const double k = settings_.skin_tie * tie_factor_ * masses_(tie.vertex);
      out->energy += 0.5 * k * s * s;
      if (derivatives) {
        out->gradient.segment<3>(3 * tie.vertex) += k * slip;
        pattern_->AddVertex(tie.vertex, k * tangential, out->hessian);
      }
    }
    if (!friction) continue;
    // Friction's hold reaches mu N at kStaticSlip: up to it a spring, beyond it a constant
    // force against the slip.
    const double k = tie_mu_[i] * tie_normal_forces_[i] / kStaticSlip;
    const double yield = kStaticSlip;
    if (s <= yield) {
      out->energy += 0.5 * k * s * s;
      if (!derivatives) continue;
      out->gradient.segment<3>(3 * tie.vertex) += k * slip;
      pattern_->AddVertex(tie.vertex, k * tangential, out->hessian);
      continue;
    }
    out->energy += k * yield * (s - 0.5 * yield);
    if (!derivatives) continue;
    const Eigen::Vector3d along = slip / s;
    out->gradient.segment<3>(3 * tie.vertex) += k * yield * along;
    pattern_->AddVertex(tie.vertex, k * yield / s * (tangential - along * along.transpose()),
                        out->hessian);
  }
  AddContacts(x, body, derivatives, out);
}

void ClothSolver::AddSprings(const core::Positions& x, bool derivatives,
                             Evaluation* out) const {
  // One spring of stiffness k and rest length `rest` between the ends of edge (i, j).
  auto add = [&](size_t e, int32_t i, int32_t j, const Eigen::Vector3d& d, double length,
                 double rest, double k) {
    if (k == 0) return;
    out->energy += 0.5 * k * (length - rest) * (length - rest);
    if (!derivatives) return;
    const Eigen::Vector3d force = length < 1e-12
                                      ? Eigen::Vector3d(k * d)
                                      : Eigen::Vector3d(k * (length - rest) / length * d);
    out->gradient.segment<3>(3 * i) += force;
    out->gradient.segment<3>(3 * j) -= force;
    const Eigen::Matrix3d block = SpringBlock(d, length, rest, k);
    Eigen::VectorXd& h = out->hessian;
    pattern_->AddVertex(i, block, h);
    pattern_->AddVertex(j, block, h);
    pattern_->Add(pattern_->Edge(e), -block, h);
  };
  for (size_t e = 0; e < model_.edges.size(); ++e) {
    const auto [i, j] = model_.edges[e];
    const Eigen::Vector3d d = (x.row(i) - x.row(j)).transpose();
    const double length = d.norm();
    const double r = edge_rest_(static_cast<Eigen::Index>(e));
    if (!elastic_edge_[e]) {
      add(e, i, j, d, length, r,
          length < r ? settings_.compression_stiffness : settings_.stretch_stiffness);
      continue;
    }
    // The band's fabric gathers on its elastic, which only pulls.
    if (length > r) add(e, i, j, d, length, r, settings_.stretch_stiffness);
    const double elastic_rest = settings_.waistband_grip * r;
    if (length > elastic_rest) add(e, i, j, d, length, elastic_rest, settings_.waistband_stiffness);
  }
}

void ClothSolver::AddBending(const core::Positions& x, bool derivatives,
                             Evaluation* out) const {
  for (size_t h = 0; h < model_.hinges.size(); ++h) {
    const double weight = hinge_weights_(static_cast<Eigen::Index>(h));
    if (weight == 0) continue;
    const auto& v = model_.hinges[h];
    const core::DihedralAngle hinge =
        core::HingeAngle(x.row(v[0]), x.row(v[1]), x.row(v[2]), x.row(v[3]));
    if (hinge.degenerate) continue;
    const double bend =
        std::remainder(hinge.angle - hinge_rest_(static_cast<Eigen::Index>(h)), 2 * M_PI);
    out->energy += 0.5 * weight * bend * bend;
    if (!derivatives) continue;
    // Gauss-Newton: the angle's own curvature is left out, which keeps the Hessian
    // positive semi-definite.
    const std::array<HessianPattern::Ref, 10>& blocks = pattern_->Hinge(h);
    int block = 0;
    for (int a = 0; a < 4; ++a) {
      out->gradient.segment<3>(3 * v[a]) += weight * bend * hinge.gradient.col(a);
      for (int b = 0; b <= a; ++b) {
        pattern_->Add(blocks[block++],
                      weight * hinge.gradient.col(a) * hinge.gradient.col(b).transpose(),
                      out->hessian);
      }
    }
  }
}

void ClothSolver::AddAreaFloor(const core::Positions& x, bool derivatives, Evaluation* out) const {
  const double k = settings_.stretch_stiffness;
  for (Eigen::Index t = 0; t < model_.triangles.rows(); ++t) {
    const double rest = triangle_rest_areas_(t);
    if (rest == 0) continue;
    const auto tri = model_.triangles.row(t);
    const Eigen::Vector3d p[3] = {x.row(tri(0)), x.row(tri(1)), x.row(tri(2))};
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double twice_area = n.norm();
    const double shortfall = settings_.area_floor - 0.5 * twice_area / rest;
    if (shortfall <= 0) continue;
    out->energy += 0.5 * k * rest * shortfall * shortfall;
    // A triangle crushed to a line has no normal, so no direction in which to reopen.
    if (!derivatives || twice_area == 0) continue;
    // d area / d corner c = normal x (the side opposite c, taken counter-clockwise) / 2.
    const Eigen::Vector3d normal = n / twice_area;
    Eigen::Vector3d grad[3];
    for (int c = 0; c < 3; ++c) grad[c] = 0.5 * normal.cross(p[(c + 2) % 3] - p[(c + 1) % 3]);
    const std::array<HessianPattern::Ref, 6>& blocks = pattern_->Triangle(t);
    int block = 0;
    for (int a = 0; a < 3; ++a) {
      out->gradient.segment<3>(3 * tri(a)) -= k * shortfall * grad[a];
      for (int b = 0; b <= a; ++b) {
        pattern_->Add(blocks[block++], k / rest * grad[a] * grad[b].transpose(), out->hessian);
      }
    }
  }
}

void ClothSolver::AddContacts(const core::Positions& x, const core::TriangleBvh& body,
                              bool derivatives, Evaluation* out) const {
  const double k = settings_.contact_stiffness;
  const double offset = settings_.collision_offset;
  Eigen::VectorXd& h = out->hessian;
  const double search = settings_.collision_search;
  out->nearest_triangles.assign(static_cast<size_t>(x.rows()), -1);
  out->clearances = Eigen::VectorXd::Constant(x.rows(), search - offset);
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    if (masses_(v) == 0) continue;
    const double floor_depth = floor_ + offset - x(v, 1);
    if (floor_depth > 0) {
      out->energy += 0.5 * k * floor_depth * floor_depth;
      if (derivatives) {
        out->gradient(3 * v + 1) -= k * floor_depth;
        Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
        block(1, 1) = k;
        pattern_->AddVertex(v, block, h);
      }
    }
    const Eigen::Vector3d p = x.row(v).transpose();
    const double moved = (x.row(v) - positions_.row(v)).norm();
    if (moved + kClearanceRounding < clearances_(v)) {
      out->nearest_triangles[v] = nearest_triangles_[v];
      out->clearances(v) = clearances_(v) - moved;
      continue;
    }
    const core::SurfacePoint hit = body.Closest(p, search, nearest_triangles_[v]);
    out->nearest_triangles[v] = hit.triangle;
    if (hit.found) out->clearances(v) = hit.signed_distance - offset;
    if (!hit.found || hit.signed_distance >= offset) continue;
    const double depth = offset - hit.signed_distance;
    out->energy += 0.5 * k * depth * depth;
    if (!derivatives) continue;
    // The signed distance's gradient: away from the closest point, or the pseudo-normal on
    // the surface itself.
    const Eigen::Vector3d normal = std::abs(hit.signed_distance) > 1e-9
                                       ? Eigen::Vector3d((p - hit.point) / hit.signed_distance)
                                       : hit.normal;
    out->gradient.segment<3>(3 * v) -= k * depth * normal;
    pattern_->AddVertex(v, k * normal * normal.transpose(), h);
  }
  for (const Poke& poke : pokes_) {
    const auto tri = model_.triangles.row(poke.triangle);
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) point += poke.barycentric(c) * x.row(tri(c)).transpose();
    const double height =
        (point - body.positions().row(poke.body_vertex).transpose()).dot(poke.normal);
    const double depth = kPokeClearance - height;
    if (depth <= 0) continue;
    out->energy += 0.5 * k * depth * depth;
    if (!derivatives) continue;
    const std::array<HessianPattern::Ref, 6>& blocks = pattern_->Triangle(poke.triangle);
    int block = 0;
    for (int a = 0; a < 3; ++a) {
      out->gradient.segment<3>(3 * tri(a)) -= k * depth * poke.barycentric(a) * poke.normal;
      for (int b = 0; b <= a; ++b) {
        pattern_->Add(blocks[block++],
                      k * poke.barycentric(a) * poke.barycentric(b) * poke.normal *
                          poke.normal.transpose(),
                      h);
      }
    }
  }
}

std::vector<ClothSolver::Poke> ClothSolver::FindPokes(const core::TriangleBvh& body) {
  std::vector<Poke> pokes;
  garment_bvh_->Refit(positions_);
  const core::Positions& bp = body.positions();
  // Area-weighted body vertex normals: enough to tell outward from inward here.
  const core::Positions normals = core::VertexNormals(bp, body.triangles());
  const Eigen::RowVector3d lo = positions_.colwise().minCoeff().array() - kPokeSearch;
  const Eigen::RowVector3d hi = positions_.colwise().maxCoeff().array() + kPokeSearch;
  for (Eigen::Index b = 0; b < bp.rows(); ++b) {
    const Eigen::RowVector3d p = bp.row(b);
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    if (normals.row(b).squaredNorm() == 0) continue;
    const core::SurfacePoint hit = garment_bvh_->Closest(p.transpose(), kPokeSearch);
    if (!hit.found) continue;
    // In a crease (armpit, crotch) the triangle may belong to the garment over the facing
    // surface; it is this vertex's only if the body under it is near this vertex.
    const core::SurfacePoint under = body.Closest(hit.point, settings_.collision_search);
    if (!under.found || (under.point - p.transpose()).norm() > kOwnSurfaceRadius) continue;
    // Only cloth over (or under) the vertex is poked, not a hem beside it, whose nearest point
    // lies along the skin. The nearest point may be on an edge between two triangles: poking
    // only triangles whose inside is nearest let female_casualsuit01's leggings snap over body
    // vertices under their edges between bodies 0.05 sigma apart (second difference 4.2 mm,
    // the same at half the step; 0.8 mm at half the step with edges poked too).
    const Eigen::Vector3d normal = normals.row(b).transpose();
    const Eigen::Vector3d up = hit.point - p.transpose();
    if (std::abs(up.dot(normal)) < kOverShare * up.norm()) continue;
    pokes.push_back({static_cast<int32_t>(b), hit.triangle, hit.barycentric, normal});
  }
  return pokes;
}

int ClothSolver::ClearTriangles(const core::TriangleBvh& body) {
  int lifted = 0;
  for (const Poke& poke : FindPokes(body)) {
    const auto tri = model_.triangles.row(poke.triangle);
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    double weight_squares = 0;
    for (int c = 0; c < 3; ++c) {
      point += poke.barycentric(c) * positions_.row(tri(c)).transpose();
      if (masses_(tri(c)) > 0) weight_squares += poke.barycentric(c) * poke.barycentric(c);
    }
    const double lack = kFinalClearance -
                        (point - body.positions().row(poke.body_vertex).transpose()).dot(poke.normal);
    if (!(lack > 0) || weight_squares == 0) continue;
    // The least change of the corners that lifts the point over the body vertex enough.
    for (int c = 0; c < 3; ++c) {
      if (masses_(tri(c)) == 0) continue;
      positions_.row(tri(c)) += (poke.barycentric(c) * lack / weight_squares) * poke.normal.transpose();
    }
    ++lifted;
  }
  return lifted;
}

Eigen::Vector3d ClothSolver::PushOut(const core::TriangleBvh& body, const core::SurfacePoint& hit,
                                     double search) const {
  Eigen::Vector3d best = hit.point + settings_.collision_offset * hit.normal;
  double best_distance = -std::numeric_limits<double>::infinity();
  // Tries `point`; true once it is outside the body.
  auto outside = [&](const Eigen::Vector3d& point, Eigen::Vector3d* normal) {
    const core::SurfacePoint there = body.Closest(point, search);
    const double distance = there.found ? there.signed_distance : search;
    if (normal != nullptr) *normal = there.normal;
    if (distance > best_distance) {
      best = point;
      best_distance = distance;
    }
    return distance > 0;
  };
  // In a crease narrower than twice the offset (an armpit) the point at the offset over one
  // side is inside the other; a point nearer this side is between them.
  Eigen::Vector3d facing = hit.normal;
  double lift = settings_.collision_offset;
  for (int halving = 0; halving < kMaxPushHalvings; ++halving, lift *= 0.5) {
    if (outside(hit.point + lift * hit.normal, halving == 0 ? &facing : nullptr)) return best;
  }
  // Where the two sides touch (thighs at a short body's crotch) there is no room between
  // them: the way out is along the crease, between the two sides' normals.
  const Eigen::Vector3d along = hit.normal + facing;
  if (along.norm() >= kMinCreaseOpening) {
    lift = settings_.collision_offset;
    for (int doubling = 0; doubling < kMaxPushDoublings; ++doubling, lift *= 2) {
      if (outside(hit.point + lift * along.normalized(), nullptr)) return best;
    }
  }
  // Where two parts of the body face each other closer than the least lift (a heavy man's
  // upper arm 0.06 mm from his side), the way along the crease may lead further in, up into
  // the armpit: then the point farthest outside at the shortest lift that leaves the body in
  // any of 26 directions (a cube's faces, edges and corners).
  for (lift = settings_.collision_offset; lift <= search; lift *= 2) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          outside(hit.point + lift * Eigen::Vector3d(dx, dy, dz).normalized(), nullptr);
        }
      }
    }
    if (best_distance > 0) return best;
  }
  return best;
}

int ClothSolver::ResolveCollisions(const core::TriangleBvh& body, double search,
                                   double below) {
  const core::Positions before = positions_;
  floor_ = body.positions().col(1).minCoeff();
  const double offset = settings_.collision_offset;
  for (Eigen::Index v = 0; v < positions_.rows(); ++v) {
    if (masses_(v) == 0) continue;
    if (positions_(v, 1) < floor_ + below) positions_(v, 1) = floor_ + offset;
    const core::SurfacePoint hit = body.Closest(positions_.row(v).transpose(), search);
    if (!hit.found || hit.signed_distance >= below) continue;
    positions_.row(v) = PushOut(body, hit, search).transpose();
  }
  return static_cast<int>(((positions_ - before).rowwise().squaredNorm().array() > 0).count());
}

}  // namespace fitbase::workers
