#ifndef FITBASE_WORKERS_CLOTH_SOLVER_H_
#define FITBASE_WORKERS_CLOTH_SOLVER_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "Eigen/Core"
#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"
#include "core/triangle_bvh.h"
#include "workers/cloth_model.h"
#include "workers/sparse_cholesky.h"

namespace fitbase::workers {

// Physical and numerical settings of the drape. Distances in meters, forces in newtons.
struct ClothSettings {
  // Time step of the implicit (backward Euler) steps, s. Velocities are dropped after every
  // step, so the mass term only keeps each step's minimisation well posed (a garment may
  // slide freely around a limb): a longer step converges faster, a shorter one moves less.
  double step_seconds = 1.0;
  // Newton iterations per step, each a sparse Cholesky solve plus a backtracking line search:
  // a step iterates until an iteration moves no vertex more than `newton_tolerance` (m), at
  // most `newton_iterations` times. Solving each step to its minimum keeps the path, and so
  // the drape, a continuous function of the body; a fixed small count stops short at a point
  // that depends on which line-search halvings happened, and a fold then settles one way or
  // the other between nearby bodies (at 4 iterations a 0.05-sigma step moved one vertex by
  // 7.7 mm more than linearly, solved to 0.1 mm by 3.5 mm). The step count stays fixed.
  int newton_iterations = 12;
  double newton_tolerance = 1e-4;
  // At most this many of those iterations in a step whose body moved since the last one (the
  // drape's path from the mean avatar to the target); steps on a body at rest (the relaxation
  // at the target) take up to `newton_iterations`. The path's shapes matter only as a way to
  // the result, and solving each to 0.1 mm took most of a drape's iterations: after four, a
  // step's moves stayed at 0.1 to 0.7 mm for up to eight more while a soft mode (cloth hanging
  // free over the chest) drifted towards its minimum. The relaxation finishes what the path
  // leaves. On 24 drapes (the 12 shared garments, two held-out bodies each) this took 1.7x
  // less time in all (1.4 to 2.1x per drape but one); 17 results moved under 0.07 mm on the
  // mean, three 0.09 to 0.15 mm, and the stretched drapes of one heavy woman, whose folds
  // have more than one resting place, 0.25 to 0.35 mm (as much as they move with 6 here, or
  // with only the path's tolerance loosened to 0.3 mm). It moves where along a line of
  // bodies a fold snaps from one resting place to the other, not whether one can: at 0.1
  // sigma 9 of the 12 garments keep the second difference's p99 under 2 mm, as before, but a
  // different three miss it (fitbase_drape_bench --smoothness-only).
  int path_newton_iterations = 4;
  double gravity = 9.81;        // Along -y, m/s^2.
  double areal_density = 0.15;  // kg/m^2, a light woven fabric.
  // Spring constants, N/m. A spring of rest length r along an edge of roughly square cloth
  // stands for a strip about r wide, so one constant for all edges is a uniform material.
  double stretch_stiffness = 2e4;  // A triangle edge longer than its rest length (quad
                                   // diagonals shear).
  // An edge shorter than its rest length. Real cloth takes compression by buckling into
  // wrinkles a few millimetres wide, far finer than a garment's 1-3 cm edges. A coarse mesh as
  // stiff in compression as in stretch can buckle only at its own scale, into folds that snap
  // between nearby bodies, or pushes the excess elsewhere: a too-long trouser leg on a short
  // body pushed its hem 9 cm down over the foot, stretching it 50 to 68%, instead of
  // gathering at the ankle. Soft compression stands for the fine wrinkles (Choi and Ko 2002).
  // A fifth of the stretch stiffness: at 0.1 sigma along component 0 the second difference's
  // p99 stays under 2 mm on 10 of the 12 shared garments (7 with compression as stiff as
  // stretch). Softer still gathers more cloth but lets other folds snap (at a tenth, one on
  // female_elegantsuit01 jumped by 22 mm).
  double compression_stiffness = 4e3;
  // Share of its rest area below which a triangle resists shrinking further, with the stretch
  // stiffness as its membrane modulus: energy k/2 * A0 * (floor - A/A0)^2. Soft compression
  // alone lets cloth pinched in a crease (between arm and torso) crush a triangle to a line;
  // its hinges then have no plane to bend about, their angles swing by pi under micrometre
  // moves, and the drape jumps between nearby bodies (female_elegantsuit01 at 0.1 sigma along
  // component 0: second difference 3.3 mm worst; 1.8 mm with the floor at half the area).
  double area_floor = 0.5;
  // Bending rigidity, N m: a hinge's energy is B/2 * 3|e|^2/(A1 + A2) * (angle - rest)^2
  // (discrete shells), with the rest angles of the garment as made. Stiffer than most cloth
  // (its bending length (B / weight)^(1/3) is 11 cm; cotton's is 2-5 cm), on purpose: softer
  // cloth buckles into folds whose place jumps between nearby bodies, and the clothing basis
  // needs drapes that vary smoothly with the body (at 2e-4 a 0.1-sigma step moved some
  // vertices by 18 mm more than linearly, at 2e-3 by 3 mm).
  double bending_rigidity = 2e-3;
  // Keeps a collar's height on the neck, and a bib overall's straps' on the shoulders
  // (relative to the skin point each vertex started over; both ring the neck, FindSupports),
  // N/m. A waistband's is `waistband_anchor_stiffness`. A shirt's front is longer than a
  // shorter man's torso, and what soft compression it keeps pushes the collar up his neck: at
  // 20 N/m, as before the supports, male_casualsuit02's sat 1.5 cm above the neck girth's
  // landmarks on the mean avatar and 2.3 to 3.4 cm on the shortest men, standing 3 cm off the
  // nape. At 200 N/m, over the 2% tails, collars of sizes that fit stay within 0.6 to 1.0 cm of
  // their height on the mean avatar (fitbase_drape_bench --supports). Its cost: the back of
  // male_worksuit01's T-shirt comes into and out of contact between nearby bodies (p99 2.6 mm
  // at 0.1 sigma, 1.2 at 20 N/m; at 50 N/m it is 1.7 and female_casualsuit02's 2.1).
  double anchor_stiffness = 200;
  // Stiction, N/m per kg of cloth (without `friction`, below): each vertex is held, along the
  // body surface only, to the point of the skin it started over, as it moves with the body.
  // Without it a frictionless garment has a continuum of resting places (it may slide around a
  // limb or settle a fold to either side) and the path decides; with it the drape is one
  // smooth function of the body.
  // Weak next to the stretch springs: it does not stop a garment stretching or lifting off.
  // Ten times as stiff, the drapes of a size too small, whose stretched cloth has more than one
  // resting place, are smoother and the fast fit learns them better (female_elegantsuit01 M at
  // 1,600 sampled drapes: 2.14 mm and 0.46% visible skin against 2.49 and 0.59%); but the ties
  // drag (hems ride up longer legs 10% less; at 1e6 half as much, and a band slides down the
  // tallest body's rise), and along a long path, from the all preset's mean avatar to the
  // average woman, they push cloth into compression whose folds jump (4 of 12 garments over
  // 2 mm at 0.1 sigma, female_elegantsuit01 19 mm; docs/drape.md, "Stiffer ties").
  double skin_tie = 1e4;
  // Ties firmer on a size too small for the body (docs/drape.md, "Firmer ties on a size too
  // small"). Stretched cloth has more than one resting place on the body, and which one the
  // path from the mean avatar reaches changes between nearby bodies; ties a hundred times as
  // stiff leave it one. Firm everywhere they drag: on a body far from the one the garment was
  // imported on they push cloth into compression whose folds jump. So they firm up only as
  // the size gets too small: the ties' stiffness, and the supports' (the band's and collars'
  // height), are times `tight_tie_factor` at a carried girth ratio of `tight_girth_full` and
  // above (ClothSolver::CarriedGirthRatio: the size on the body were the cloth carried with
  // the skin), times 1 at `tight_girth_from` and below, and between them a smoothstep of the
  // ratio in the factor's logarithm. The supports firm up with the ties, or the firm ties of a
  // long leg drag leggings' band down it (over the 2% tails of 500 women the band's worst
  // change on the rise was 3.8 cm with firm ties alone, 2.0 cm with neither firm and 0.7 with
  // both). A body in the ramp may be rough: a step of 0.1 sigma changes the factor by up to a
  // third, and more in a narrower ramp (at 1.03 to 1.08 the women in it jumped; at 0.98 to
  // 1.03 male_casualsuit03 went over 2 mm at the average man). A ramp of 1.00 to 1.04, above
  // every average body and below most sizes too small, was smoother around held-out women (3
  // of 30 drapes over 2 mm against 6) but the fast fit learnt its drapes worse (2.45 mm and
  // 0.58% visible skin against 2.31 and 0.50%; likely the drape turning too fast across so
  // narrow a ramp; docs/drape.md, "A narrower ramp, tried, not kept"). The ratio is of the
  // body alone, known before the drape, so the drape stays one smooth function of it; a stiffness
  // that followed the cloth's own pressure (the contact's lagged normal force) fed back on
  // itself, and 5 of the 12 garments jumped by 4 to 17 mm at the average bodies.
  double tight_tie_factor = 100;
  double tight_girth_from = 0.98;
  double tight_girth_full = 1.10;
  // With `friction` > 0 the ties are Coulomb friction instead (issue "The drape is true far
  // from the mean"): a vertex is held to its skin point up to mu times its contact's normal
  // force, then slips, and the place it slipped to is where it is held from then on. The
  // normal force is the contact's at the end of the previous step (lagged, as IPC does); a
  // vertex off the body is not held. Below 1 mm of slip (kStaticSlip) the hold is a spring
  // reaching the limit there, so each step's energy stays smooth for Newton. Every step of the
  // path is solved to the tolerance (path_newton_iterations is not used): friction has
  // memory, and a step stopped short leaves it in a place that depends on the step count
  // (female_casualsuit01 at mu 0.4 with 4 iterations a path step: second difference p99
  // 22.6 mm at 0.1 sigma, doubling the schedule moved it 3.3 mm; solved, 4.2 mm and 0.17 mm).
  // Off by default (docs/drape.md, "Coulomb friction"): at mu 0.8, the best of 0.2, 0.4 and 0.8 on
  // female_casualsuit01, six of the 12 garments jump between nearby bodies at the average body
  // (p99 2.3 to 43.7 mm at 0.1 sigma, against one with the ties); over the population's 2%
  // tails the hems ride up less, and male_worksuit01, too short for the tallest body, slides
  // its straps 19 cm down it with 0.7% of its vertices inside (with the ties its straps move
  // at most 1.8 cm over the tails, and no vertex is inside); and a drape takes 2 to 6.5 times
  // as long.
  double friction = 0;
  // Coulomb friction's mu on declared cuffs' vertices (Supports::cuffs), on top of their ties
  // (with `friction` as well, the larger mu, in place of them): the issue asks that cuffs grip
  // with high friction. The elastic presses a snug cuff onto the limb, and this holds it there
  // up to mu times that pressure, where a tie holds it with the weak stiction of any cloth; a
  // cuff off the skin is held by its tie alone. 0: the ties alone. Off by default, as cuffs
  // are (docs/drape.md, "Cuffs that grip by friction"): with all 12 shared garments declared
  // with both cuffs, at mu 0.25 every drape is smooth at the average bodies (p99 at most 1.87 mm
  // at 0.1 sigma; with the ties alone two sleeve cuffs jumped, 2.56 and 2.90 mm), but friction
  // as high as skin's makes them jump (at mu 1 four over 2 mm, one 16 mm), and the path's steps
  // are solved to the tolerance, which doubles a drape's time.
  double cuff_friction = 0;
  // Supports for bodies far from the mean (README, "Bodies far from the mean"; issue "The drape
  // is true far from the mean"): an elastic waistband held at its height, below, and collars
  // held at theirs, above. On by default: without them a tall body's stiction drags leggings'
  // bands 20 cm down the rise. Their cost: a held collar kinks between nearby bodies on 1 of
  // the 12 shared garments (p99 2.6 mm at 0.1 sigma). Until the supports were only openings
  // that ring the body (FindSupports), the open fronts of three jackets and shirts carried an
  // elastic, and their drapes jumped (p99 3.7 to 20 mm). The fast fit learns the supported
  // drapes no worse: kernel 5.41 mm against 5.54 at 100 samples, 4.08 against 4.08 at 400,
  // with less skin through the cloth (0.37% against 0.47%); with the collars held, 4.83 mm
  // against 4.97 on four garments at 100 samples. WithoutSupports turns them off, to compare.
  // With `waistband_stiffness` > 0 a waistband (the highest opening of trousers and skirts,
  // round the torso: FindSupports) is elastic: its boundary edges carry an elastic of rest
  // length `waistband_grip` times the size's, of that stiffness (N/m), and the fabric along it
  // gathers freely (no compression stiffness). Its height on the body is held by
  // `waistband_anchor_stiffness` (N/m), with the elastic or without. The band's rest girth is
  // then below the waists it fits, so it grips a slim and a broad waist alike. Not far below:
  // fabric gathered on an elastic half the band's length folds one way or another, and at 0.5
  // male_casualsuit03's drape jumped between nearby bodies (p99 16.6 mm at 0.1 sigma; 0.9 mm at
  // 0.85). A band more than 1 / 0.85 = 18% wider than the waist hangs loose. Its height is
  // held ten times as hard as a collar's: at 1000 N/m two garments' bands moved 2.3 to
  // 2.4 cm on the rise over the population's 2% tails, at 1500 and 4000 N/m other garments'
  // folds jumped between nearby bodies.
  double waistband_grip = 0.85;
  double waistband_stiffness = 3000;
  double waistband_anchor_stiffness = 2000;
  // Where that height is kept on an avatar. False: each band vertex over the skin point it
  // started over, as collars are. True: the same, with the band as a whole shifted to keep its
  // mean place on the crotch-to-navel rise, as on the body the drape starts on. The body
  // model's skin slides over the landmarks from one body to the next (on a heavy man the navel
  // sinks towards the crotch, and the skin under male_casualsuit02's band rises from 75% to
  // 83% of his rise), and an elastic band grips at the waist, not at a point of the skin.
  bool waistband_on_rise = true;
  // Contact: energy k/2 * depth^2 for a vertex `depth` inside the offset, N/m. Quadratic, so
  // that Newton resolves a contact in one iteration. Soft enough that the body's facets and
  // creases do not stall the line search (at 1e7 the drape changed by millimetres when the
  // body moved by a micrometre), stiff enough that a tight garment's few newtons per vertex
  // sink it well under a millimetre into the offset.
  double contact_stiffness = 2e4;
  double collision_offset = 0.0025;
  double collision_search = 0.03;  // Penetrations deeper than this are not seen.
  // Both factorisations give the same drape to rounding. Supernodal, with the OpenBLAS
  // scripts/setup.sh selects (on one thread), is 6.2x faster on an 8.4k-vertex garment.
  Factorization factorization = Factorization::kSupernodalCholmod;
};

// Names what the solver computes: bumped whenever the solver or the drape pipeline changes
// results for the same inputs. Drape keys carry it, and so do garment import ids, since the
// import fits the garment to the mean avatar with this solver (FitTemplateToBody).
// fitbase-newton-15 (the firm ties' ramp at 1.00 to 1.04) was withdrawn: the drape is
// newton-14's again to the bit, so it takes that name back and caches keyed by it stay good.
inline constexpr char kSimulatorVersion[] = "fitbase-newton-14";

// N/m holding collars and waistbands at their height without the supports.
inline constexpr double kUnsupportedAnchorStiffness = 20;

// The largest ClothSettings::friction a drape takes. Cloth on skin is about 0.3 to 0.8; far
// above, the static hold's stiffness (mu N per millimetre) would swamp the Newton systems.
inline constexpr double kMaxFriction = 10;

// InvalidArgument, naming `name` and the value, unless `mu` is finite and in [0, kMaxFriction]:
// the one check of ClothSettings::friction and cuff_friction for every caller (a build's spec,
// the command line, the bench).
absl::Status CheckFriction(double mu, absl::string_view name);

// The largest ClothSettings::skin_tie a drape takes, N/m per kg of cloth. A vertex weighs about
// 0.1 g, so a tie is then about 1,000 N/m: beyond, the ties would near the cloth's own springs
// and its contact (2e4 N/m), and the garment could not leave the skin points it started over.
inline constexpr double kMaxSkinTie = 1e7;

// InvalidArgument, naming `name` and the value, unless `tie` is finite and in [0, kMaxSkinTie]:
// the one check of ClothSettings::skin_tie for every caller (a build's spec as `skin_tie`, the
// command line as `--skin-tie`).
absl::Status CheckSkinTie(double tie, absl::string_view name);

// The largest ClothSettings::tight_tie_factor a drape takes. At 100 (the default) the ties
// near the cloth's own springs; a thousand times the default ties would reach kMaxSkinTie.
inline constexpr double kMaxTightTieFactor = 1e3;

// InvalidArgument, naming the setting and its value, unless ClothSettings::tight_tie_factor is
// finite and in [1, kMaxTightTieFactor] (1: never firmer) and the ramp's ends
// tight_girth_from <= tight_girth_full are finite and in [0.5, 2]: the one check of the firm
// ties' settings for every caller (the bench's --tight-* flags).
absl::Status CheckTightTies(const ClothSettings& settings);

// How much firmer the ties and supports are for a drape onto a body of carried girth ratio
// `girth_ratio` (ClothSolver::CarriedGirthRatio): 1 to ClothSettings::tight_tie_factor.
double TightTieFactor(const ClothSettings& settings, double girth_ratio);

// `settings` with the supports for bodies far from the mean off: no elastic, and the waistband
// and collars held at kUnsupportedAnchorStiffness, as every drape was before them (simulator
// fitbase-newton-8 with the older defaults). On the 2% tails of 500 sampled avatars
// unsupported leggings' bands slide 20 cm down the rise, supported ones stay within 1.7 cm
// (fitbase_drape_bench --supports).
ClothSettings WithoutSupports(ClothSettings settings);

// Quasi-static cloth: every step minimises the garment's elastic, gravity, stiction and contact
// energy plus a mass-weighted proximity term to the previous step (a backward Euler step from
// rest) by Newton iterations to a tolerance (sparse Cholesky with a fill-reducing ordering
// and symbolic analysis computed once, Armijo backtracking, no vertex moved by more than half
// the collision search in one iteration). A global solve keeps near-inextensible edges at their
// length where a few local (Gauss-Seidel, XPBD) sweeps leave them stretched. Everything runs
// in a fixed order, so a run is bitwise reproducible.
class ClothSolver {
 public:
  // `start` (V x 3, m) on the body `body`; rest lengths per model.edges (m) and rest angles
  // per model.hinges (rad); `supports`: its waistbands, whose edges carry the elastic
  // (ClothSettings::waistband_grip), collars (FindSupports) and cuffs (FindCuffs), whose edges
  // carry the same elastic. The top openings (each piece's highest, model.openings) are anchored
  // to the body surface nearest them on `body`: waistbands at
  // ClothSettings::waistband_anchor_stiffness (on an avatar, shifted with its rise:
  // waistband_on_rise), collars and straps at anchor_stiffness, the others at
  // kUnsupportedAnchorStiffness.
  ClothSolver(const ClothModel& model, const core::Positions& start, Eigen::VectorXd edge_rest,
              Eigen::VectorXd hinge_rest, const Supports& supports, const core::TriangleBvh& body,
              const ClothSettings& settings);

  // One step with the body as `body` now is (the caller refits it between steps): at most
  // ClothSettings::path_newton_iterations Newton iterations when the body moved since the
  // last step (or since construction), else up to newton_iterations; up to newton_iterations
  // always with friction on any tie, whose memory needs each step solved. Returns the largest
  // vertex move of the step, meters.
  double Step(const core::TriangleBvh& body);

  // Pushes every vertex closer to the body than `below` (or inside, up to `search` deep) out
  // to the collision offset along the body's pseudo-normal (less in a narrow crease);
  // returns how many moved.
  int ResolveCollisions(const core::TriangleBvh& body, double search, double below);

  // Lifts every garment triangle that lies less than 1.5 mm over a body vertex under it (found
  // as the pokes are, on the garment as it now is) by the least change of its corners along
  // that vertex's normal, one triangle after another; returns how many were lifted. Contact is
  // a penalty, and a garment stretched tight over a large body presses its triangles' middles
  // into the skin between the corners, which keep their offset.
  int ClearTriangles(const core::TriangleBvh& body);

  const core::Positions& positions() const { return positions_; }

  // The garment's girth on `body` (the start body moved: its vertex count x 3, m, with its
  // `triangles`) were each vertex carried with the skin point it is tied to, keeping its
  // offset from it, over the size's: the sum of h_e |x_i - x_j| over the sum of h_e r_e, over
  // the model's edges (i, j) of rest length r_e, each weighted by its share across the body at
  // the start, h_e = 1 minus its direction's vertical component squared. 1 where the body
  // needs the size's girth, above 1 where the size is too small for it. Of the body alone,
  // smooth in it, and taken before the first step (vertices no face uses stay where they are).
  double CarriedGirthRatio(const core::Positions& body, const core::Triangles& triangles) const;

  // Multiplies the stiffness of the ties (ClothSettings::skin_tie) and of the supports'
  // anchors by `factor` from the next step on. Without ClothSettings::friction only (a cuff's
  // friction is not firmed).
  void FirmTies(double factor) { tie_factor_ = factor; }

  ~ClothSolver();

 private:
  // The body surface point nearest a vertex at the start, which moves with the body.
  struct SkinPoint {
    int32_t triangle;
    Eigen::Vector3d barycentric;
  };
  struct SkinTie {
    int32_t vertex;
    SkinPoint skin;
    // Where the vertex is held minus the skin point, m: at the start, its start position's.
    Eigen::Vector3d offset;
  };
  struct AnchorBinding {
    int32_t vertex;
    SkinPoint skin;
    double height_above;  // Vertex height minus the skin point's height, m.
    double stiffness;     // N/m.
    int32_t band;         // Its index into band_shares_, or -1: held over its skin point alone.
  };
  // Sets where the anchors and ties are held on `body`, the body of this step:
  // anchor_over_skin_, band_shifts_ and tie_holds_.
  void HoldAnchors(const core::TriangleBvh& body);
  // A body vertex under a garment triangle: vertex-only contact lets a coarse triangle cut
  // through a convex body between its corners, so the triangle's point over the body vertex
  // (fixed barycentric coordinates) keeps a clearance too. Found when the body stops moving.
  struct Poke {
    int32_t body_vertex;
    int32_t triangle;
    Eigen::Vector3d barycentric;
    Eigen::Vector3d normal;  // The body vertex's outward normal.
  };
  // Energy, gradient and Gauss-Newton Hessian of the garment at `x` (V x 3).
  struct Evaluation {
    double energy = 0;
    Eigen::VectorXd gradient;  // 3V.
    Eigen::VectorXd hessian;   // As the factorisation takes them (HessianPattern).
    // Per vertex, at the evaluated positions: see nearest_triangles_ and clearances_.
    std::vector<int32_t> nearest_triangles;
    Eigen::VectorXd clearances;
  };
  class HessianPattern;

  // Where `skin` is on the body as it now is, m.
  static Eigen::Vector3d OnSkin(const core::TriangleBvh& body, const SkinPoint& skin);
  // The body vertices under the garment's triangles as it now is.
  std::vector<Poke> FindPokes(const core::TriangleBvh& body);
  // Where a vertex inside the body, nearest `hit` on its surface, is put (m): at the collision
  // offset along the surface normal; nearer the surface where that point is inside another
  // part of the body; out along the crease where the two parts touch; else the nearest way out
  // in any direction, up to `search` away. The point tried that is farthest outside when none
  // is.
  Eigen::Vector3d PushOut(const core::TriangleBvh& body, const core::SurfacePoint& hit,
                          double search) const;
  // With `derivatives` false only the energy is computed (for the line search).
  void Evaluate(const core::Positions& x, const core::TriangleBvh& body, bool derivatives,
                Evaluation* out) const;
  void AddSprings(const core::Positions& x, bool derivatives, Evaluation* out) const;
  void AddBending(const core::Positions& x, bool derivatives, Evaluation* out) const;
  void AddAreaFloor(const core::Positions& x, bool derivatives, Evaluation* out) const;
  // Looks up on the body only the vertices of `x` that may be within the collision offset,
  // by clearances_.
  void AddContacts(const core::Positions& x, const core::TriangleBvh& body, bool derivatives,
                   Evaluation* out) const;
  // With friction on any tie, after a step on `body`: carries each friction tie that slipped past
  // kStaticSlip along with its vertex, to kStaticSlip behind it, and takes each tied vertex's
  // contact normal force for the next step.
  void SlipTies(const core::TriangleBvh& body);
  // One Newton iteration towards the step's minimum; returns the largest vertex move (m), 0
  // when it made no progress.
  double NewtonIteration(const core::TriangleBvh& body);

  const ClothModel& model_;
  ClothSettings settings_;
  Eigen::VectorXd edge_rest_;
  Eigen::VectorXd hinge_rest_;
  // Per model edge, its share across the body at the start: 1 minus its direction's vertical
  // component squared (0 for a weld).
  Eigen::VectorXd edge_across_;
  Eigen::VectorXd hinge_weights_;  // B * 3|e|^2 / (A1 + A2) on the start shape, N m.
  Eigen::VectorXd triangle_rest_areas_;  // Per model triangle, m^2.
  Eigen::VectorXd masses_;  // Per vertex, kg; 0 for vertices no face uses (they never move).
  std::vector<AnchorBinding> anchors_;
  // Per waistband held on the rise (ClothSettings::waistband_on_rise): its anchored vertices'
  // mean place on the crotch-to-navel rise (0 at the crotch, 1 at the navel) on the start body.
  std::vector<double> band_shares_;
  // On the body of the current step (HoldAnchors), which every evaluation of the step shares:
  // per anchors_, the height over its skin point it is held at, m; per band_shares_, how far
  // the band is shifted from over its skin points, m.
  std::vector<double> anchor_over_skin_;
  std::vector<double> band_shifts_;
  std::vector<SkinTie> ties_;
  // Per ties_, on the body of the current step (HoldAnchors): where the tie pulls its vertex
  // and the normal of the skin under it, m.
  struct TieHold {
    Eigen::Vector3d target;
    Eigen::Vector3d normal;
  };
  std::vector<TieHold> tie_holds_;
  double tie_factor_ = 1;  // FirmTies.
  // Per ties_: its friction's mu (ClothSettings::friction, or cuff_friction on a cuff), 0 for
  // a stiction tie; and with friction, the normal force of the body's contact on the vertex at
  // the end of the last step (or at the start), N.
  std::vector<double> tie_mu_;
  bool friction_ = false;  // Whether any tie is friction.
  std::vector<double> tie_normal_forces_;
  std::vector<bool> elastic_edge_;  // Per model edge: a waistband's or a cuff's.
  std::vector<Poke> pokes_;
  std::optional<core::TriangleBvh> garment_bvh_;
  // Contact lookups took a quarter of a drape's time before these. Per vertex, on the body of
  // the current step:
  // - the body triangle nearest it at positions_ as last seen (-1: none within the collision
  //   search), where its next query starts. An iteration moves a vertex by millimetres, so
  //   the nearest triangle rarely changes, and starting there leaves most of the tree
  //   unsearched;
  // - at most its signed distance to the body at positions_ less the collision offset, m (the
  //   search less the offset where nothing is nearer; -infinity before the step's first
  //   lookup). The distance changes no faster than the vertex moves, and on a closed body (the
  //   avatars are: every edge has two triangles) its sign only where it is 0, so a vertex that
  //   has moved less than this since cannot have reached the offset, and needs no lookup.
  //   Most of a garment hangs that far off the body.
  std::vector<int32_t> nearest_triangles_;
  Eigen::VectorXd clearances_;
  // The floor the body stands on (its lowest point), m: long hems rest on it instead of
  // hanging through it under the feet.
  double floor_ = 0;
  core::Positions positions_;
  core::Positions step_start_;  // Where the current step began: the proximity term's centre.
  core::Positions last_body_;  // The body of the previous step, or the solver's start.
  bool stepped_ = false;       // Whether a step was taken: the first has no previous body.
  bool pokes_found_ = false;
  // The Hessian's sparsity never changes, so its fill-reducing ordering is computed once.
  std::unique_ptr<const HessianPattern> pattern_;
  SparseCholesky cholesky_;
};

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_CLOTH_SOLVER_H_
