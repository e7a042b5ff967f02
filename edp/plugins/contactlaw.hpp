// contactlaw.hpp: the nodal contact laws of the suite, defined once (paper (2.17), (2.18),
// (2.28), (2.29), in the resolvent form of (4.8); docs/design.md, section "Nodal laws").
//
// Every solver and every output reads the law from here: the compiled Newton (default),
// its script view (-kernel script), the fixed point and the full-system Newton (through
// the kernel's FreeFEM functions, edp/plugins/kernel/bindings.cpp), the record of each step,
// the statuses of contact.txt, and the scene reader (the damping families and their checks).
// Change the law in the first part of this file and ./run.sh rebuilds the kernel; every
// solver then solves the new law.
//
// First part, what a student changes: the damping families (p, p' and the check of a scene
// line's numbers, one row each in dampingFamilies), the friction bound, the statuses, the
// zones. Second part, derived from it: the family table's use (lookup, checks, messages),
// the pieces of each slot, their resolvents and relations, the fixed point's local disk
// solve, and checkLaw and checkBound, which the kernel runs when a run starts.
#ifndef CONTACTLAW_HPP
#define CONTACTLAW_HPP
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace contactlaw {

// The data of the law, set from edp/lib/contact.idp: by name (contactKernelParameter), the
// scene's damping family and its numbers (contactKernelDamping), its bound_profile or
// bound_table (contactKernelBoundProfile, contactKernelBoundTable) and, per node, the bound g
// at its position (contactKernelNodes).
struct Parameters {
  int damping = 0;       // the family of p: its row in dampingFamilies below
  double cnu = 0;        // option -cnu: C of a family whose first number is C (its default: the scene's C)
  std::vector<double> numbers;   // the family's other numbers, in the scene line's order (after C)
  double mu = 0;         // option -mu: friction coefficient
  double eps = 1;        // option -eps: penalty parameter
  bool penalty = false;  // option -problem penalty (else the original problem, v_nu <= g)
  bool literal = false;  // option -penaltyform literal (else compliant)
  double g = 0;          // option -g: the velocity bound, where the scene gives no bound_profile or bound_table
  std::vector<double> profileX, profileG;   // the scene's bound_profile x0 g0 x1 g1 ... (empty: none)
  // the scene's bound_table A a1 .. aN B b1 .. bM g G11 .. G1M .. GN1 .. GNM (empty: none): the
  // axes A, B of the grid (0 x, 1 y, 2 z), its lines along each, and its values row by row,
  // tableG[i M + j] at (a_i, b_j)
  int tableAxisA = 0, tableAxisB = 2;
  std::vector<double> tableA, tableB, tableG;
};

// A number as the messages of this file write it.
inline std::string lawNumber(double x) { char b[32]; std::snprintf(b, sizeof b, "%g", x); return std::string(b); }

// ======================= the law: what a user or a student changes =======================

// The families of the damped response p a scene can choose, "damping NAME numbers..."
// (docs/design.md, section "Scenes"). Each is p and its slope p' at r > 0 (dampedResponse below
// gives 0 at r <= 0), and the check of the scene line's numbers. A family of your own: its
// two functions, its check, and a row in dampingFamilies (docs/walkthrough.md, Exercise 1b).

// damping linear C: p(r) = C r_+, the paper's (C is -cnu). (The "// Linear" marks let
// tests/suites/10-solvers.sh find these two lines: it writes Exercise 1 of docs/walkthrough.md,
// p = C r^2, into a copy of the suite.)
inline double linearResponse(const Parameters &P, double r) {
  return P.cnu * r;                                                      // Linear
}
inline double linearSlope(const Parameters &P, double r) {
  return P.cnu;                                                          // Linear
}
inline std::string linearCheck(const std::vector<double> &x) {
  return x[0] >= 0 ? "" : "C must be >= 0, got " + lawNumber(x[0]);
}

// damping power C ALPHA: p(r) = C r_+^ALPHA, ALPHA >= 1 (C is -cnu; numbers[0] is ALPHA)
inline double powerResponse(const Parameters &P, double r) { return P.cnu * std::pow(r, P.numbers[0]); }
inline double powerSlope(const Parameters &P, double r) { return P.numbers[0] * P.cnu * std::pow(r, P.numbers[0] - 1); }
inline std::string powerCheck(const std::vector<double> &x) {
  if (!(x[0] >= 0)) return "C must be >= 0, got " + lawNumber(x[0]);
  return x[1] >= 1 ? "" : "ALPHA must be >= 1, got " + lawNumber(x[1]);
}

// The weighted mean (1 - s) y0 + s y1 of two values, 0 <= s <= 1, kept between them (y0 + (y1 -
// y0) s could round outside: 1 + (1e-17 - 1) is 0): the tables and the bound profile below
inline double keptBetween(double y0, double y1, double s) {
  return std::min(std::max((1 - s) * y0 + s * y1, std::min(y0, y1)), std::max(y0, y1));
}
// Where x lies from x0 to x1 (x0 < x1), as a fraction: halved first, so that knots whose
// distance overflows (-1e308 to 1e308) still give it
inline double fractionBetween(double x0, double x1, double x) { return (0.5 * x - 0.5 * x0) / (0.5 * x1 - 0.5 * x0); }

// damping table r0 p0 r1 p1 ...: p piecewise linear through the points (numbers: r0 p0 r1 p1
// ...), from (0, 0), nondecreasing, extended past the last point by its slope. At r > 0, the
// segment (r_k, r_k+1] that holds r (the last one beyond it).
inline int tableSegment(const Parameters &P, double r) {
  const int points = (int)P.numbers.size() / 2;
  int k = 0;
  while (k + 2 < points && r > P.numbers[2 * (k + 1)]) k++;
  return k;
}
inline double tableSlope(const Parameters &P, double r) {
  const int k = tableSegment(P, r);
  const double *point = P.numbers.data() + 2 * k;   // r_k, p_k, r_k+1, p_k+1
  return (point[3] - point[1]) / (point[2] - point[0]);
}
// Between two points, a weighted mean of their values, kept between them (p_k + slope (r - r_k)
// could round outside); past the last point, its slope.
inline double tableResponse(const Parameters &P, double r) {
  const int k = tableSegment(P, r);
  const double *point = P.numbers.data() + 2 * k;
  const double r0 = point[0], r1 = point[2], p0 = point[1], p1 = point[3];
  if (r > r1) return p1 + tableSlope(P, r) * (r - r1);
  return keptBetween(p0, p1, fractionBetween(r0, r1, r));
}
inline std::string tableCheck(const std::vector<double> &x) {
  const int points = (int)x.size() / 2;
  auto point = [&](int k) { return "point " + std::to_string(k + 1) + " (" + lawNumber(x[2 * k]) + ", " + lawNumber(x[2 * k + 1]) + ")"; };
  for (int k = 1; k < points; k++)
    if (!(x[2 * k] > x[2 * k - 2])) return point(k) + " does not come after the one before";
  if (points < 2) return "at least two points, from (0, 0)";
  if (x[0] != 0 || x[1] != 0) return "the first point must be (0, 0), got (" + lawNumber(x[0]) + ", " + lawNumber(x[1]) + ")";
  for (int k = 1; k < points; k++)
    if (x[2 * k + 1] < x[2 * k - 1]) return "p decreases at " + point(k);
  return "";
}

struct DampingFamily {
  const char *name;          // the word after "damping" on a scene line
  const char *spelling;      // its numbers, as messages and docs spell them
  int count;                 // how many numbers; 0: pairs "r p", as many as given
  bool firstIsC;             // its first number is C: the default of -cnu, which overrides it
  double (*response)(const Parameters &, double);   // p(r) at r > 0
  double (*slope)(const Parameters &, double);      // p'(r) at r > 0
  std::string (*check)(const std::vector<double> &);   // why the line's numbers (C included) cannot be used, or ""
};
const DampingFamily dampingFamilies[] = {
  {"linear", "C", 1, true, linearResponse, linearSlope, linearCheck},
  {"power", "C ALPHA", 2, true, powerResponse, powerSlope, powerCheck},
  {"table", "r0 p0 r1 p1 ...", 0, false, tableResponse, tableSlope, tableCheck},
};

// p(r), the normal damped response (2.17); the paper's is p(r) = c_nu r_+ (section 5).
// It must vanish for r <= 0 and be nondecreasing.
inline double dampedResponse(const Parameters &P, double r) {
  if (r <= 0) return 0.;
  return dampingFamilies[P.damping].response(P, r);
}

// p'(r), its slope (Newton's linearization uses it); at a kink, the slope on the left.
// Keep it consistent with dampedResponse: the kernel compares the two when a run starts.
inline double dampedResponseSlope(const Parameters &P, double r) {
  if (r <= 0) return 0.;
  return dampingFamilies[P.damping].slope(P, r);
}

// The friction bound (2.18): mu p(v_nu). At the bound v_nu = g it is Tresca's F_b = mu p(g).
inline double frictionBound(const Parameters &P, double vn) { return P.mu * dampedResponse(P, vn); }
inline double frictionBoundSlope(const Parameters &P, double vn) { return P.mu * dampedResponseSlope(P, vn); }

// The cell of a grid X (increasing) that holds x: the points k0, k1 around it and the weight s
// of X[k1] (x = (1 - s) X[k0] + s X[k1]); outside the grid, its end (k0 = k1, s = 0): constant
// beyond its first and last points.
inline void gridCell(const std::vector<double> &X, double x, size_t &k0, size_t &k1, double &s) {
  s = 0;
  if (x <= X[0]) { k0 = k1 = 0; return; }
  for (size_t k = 1; k < X.size(); k++)
    if (x <= X[k]) { k0 = k - 1; k1 = k; s = fractionBetween(X[k - 1], X[k], x); return; }
  k0 = k1 = X.size() - 1;
}

// The velocity bound g of a contact node at position (x, y, z) (position[3]; z = 0 in 2D): the
// option -g; or the scene's bound_profile, piecewise linear in x through its points (between
// two, keptBetween), constant outside; or its bound_table, bilinear on the grid of its two axes
// (A, B): between the four values around the node, the weighted mean along B of each pair, then
// of the two along A, each kept between its two values (keptBetween), so g stays between the
// cell's values; constant beyond the grid's lines (the nearest line's values). The kernel gives
// every node its g from here (contactKernelNodes) and checks it (checkBound below); the scene
// reader checks the points (increasing, every g > 0, the largest at most 1e4 the smallest).
inline double velocityBound(const Parameters &P, const double *position) {
  size_t a0, a1, b0, b1;
  double s, t;
  if (!P.tableG.empty()) {
    const std::vector<double> &G = P.tableG;
    const size_t M = P.tableB.size();
    gridCell(P.tableA, position[P.tableAxisA], a0, a1, s);
    gridCell(P.tableB, position[P.tableAxisB], b0, b1, t);
    return keptBetween(keptBetween(G[a0 * M + b0], G[a0 * M + b1], t), keptBetween(G[a1 * M + b0], G[a1 * M + b1], t), s);
  }
  if (P.profileX.empty()) return P.g;
  gridCell(P.profileX, position[0], a0, a1, s);
  return keptBetween(P.profileG[a0], P.profileG[a1], s);
}

// The force scale of a node of bound g: p(g), or 1 where p(g) = 0 (a stress is measured
// against it: the residual, the end-of-run checks, contact.txt's column force_scale).
inline double forceScale(const Parameters &P, double g) {
  const double pg = dampedResponse(P, g);
  return pg > 0 ? pg : 1.;
}

// Statuses of a node (contact.txt): normal 0 free (v_nu <= 0), 1 damped, 2 at the bound
// (v_nu >= g (1 - 1e-6)); tangential 0 stick (|v_tau| <= 1e-6 g), 1 slip.
const double statusTolerance = 1e-6;
inline int normalStatus(double vn, double g) { return vn <= 0 ? 0 : (vn >= g * (1 - statusTolerance) ? 2 : 1); }
inline int tangentialStatus(double vt, double g) { return std::fabs(vt) <= statusTolerance * g ? 0 : 1; }
// (in 3D, vt is the length |v_tau| of the node's tangential velocity)
// Zones: 0 free, 1 damped-slip, 2 damped-stick, 3 bound-slip, 4 bound-stick; their names, as
// the outputs spell them (the counts zone_NAME of contact_history.txt and summary.txt).
inline int zone(int normal, int tangential) { return normal > 0 ? 2 * normal - tangential : 0; }
const char *const zoneNames[] = {"free", "damped_slip", "damped_stick", "bound_slip", "bound_stick"};
const int zoneCount = sizeof zoneNames / sizeof zoneNames[0];
// The points of Gamma3 the paper marks (Figure 3): x_B, the smallest x of a node at the bound,
// and x_C, the smallest x of a node in contact that sticks.
inline bool marksB(int normal, int) { return normal == 2; }
inline bool marksC(int normal, int tangential) { return normal > 0 && tangential == 0; }
// Where between two nodes a zone ends (x_B_estimate, x_C_estimate): the law's switching
// functions, >= 0 on the piece and < 0 off it, vanishing where the piece ends, interpolated
// along Gamma3 between a node on the piece and its neighbour off it. At the bound: the normal
// stress beyond p(g) plus the velocity beyond g at the scale p(g)/g (in a damped zone both are
// negative, at the bound both >= 0, and both vanish where the bound zone begins). Slip: the
// tangential stress beyond the friction bound mu p(v_nu) plus the slip velocity at that scale
// (stick: the first < 0 and the second 0; slip: the first 0 and the second > 0).
inline double switchScale(const Parameters &P, double g) { return forceScale(P, g) / g; }
inline double boundSwitch(const Parameters &P, double pn, double vn, double g) {
  return pn - dampedResponse(P, g) + switchScale(P, g) * (vn - g);
}
inline double slipSwitch(const Parameters &P, double lambdaTau, double vTau, double vn, double g) {
  return lambdaTau - frictionBound(P, vn) + switchScale(P, g) * vTau;   // lambdaTau, vTau: lengths
}

// ============ derived from the law above: pieces, resolvents, relations (no need to edit) ============
//
// The damping families, as the scene reader and the kernel use them: the family of a name
// (-1: none), the scene line's numbers checked (their count, then the family's own check),
// and the families spelt for messages.
const int dampingFamilyCount = sizeof dampingFamilies / sizeof dampingFamilies[0];
inline int findDampingFamily(const std::string &name) {
  for (int k = 0; k < dampingFamilyCount; k++) if (name == dampingFamilies[k].name) return k;
  return -1;
}
// why the numbers of a line "damping NAME numbers..." cannot be used, or "" (every number is
// finite: the scene reader checks that first)
inline std::string checkDampingNumbers(int family, const std::vector<double> &numbers) {
  const DampingFamily &f = dampingFamilies[family];
  const int n = (int)numbers.size();
  if (f.count == 0 && (n < 2 || n % 2)) return "needs pairs of numbers, " + std::string(f.spelling);
  if (f.count > 0 && n != f.count)
    return "takes " + std::to_string(f.count) + (f.count == 1 ? " number, " : " numbers, ") + f.spelling + ", got " + std::to_string(n);
  return f.check(numbers);
}
// "damping linear C, damping power C ALPHA, or damping table r0 p0 r1 p1 ..."
inline std::string dampingSyntax() {
  std::string text;
  for (int k = 0; k < dampingFamilyCount; k++)
    text += std::string(k == 0 ? "" : (k + 1 == dampingFamilyCount ? (k > 1 ? ", or " : " or ") : ", ")) + "damping "
            + dampingFamilies[k].name + " " + dampingFamilies[k].spelling;
  return text;
}
// the families whose first number is C, "linear or power"
inline std::string dampingNamesWithC() {
  std::vector<std::string> names;
  for (int k = 0; k < dampingFamilyCount; k++) if (dampingFamilies[k].firstIsC) names.push_back(dampingFamilies[k].name);
  std::string text;
  for (size_t k = 0; k < names.size(); k++) text += (k == 0 ? "" : (k + 1 == names.size() ? " or " : ", ")) + names[k];
  return text;
}
// The family and its numbers into P: the numbers after C for a family with C (C itself is
// P.cnu, from the option -cnu), all of them otherwise.
inline void setDamping(Parameters &P, int family, const std::vector<double> &numbers) {
  P.damping = family;
  P.numbers.assign(numbers.begin() + (dampingFamilies[family].firstIsC && !numbers.empty() ? 1 : 0), numbers.end());
}

// Slots. A contact node carries up to two slots, its normal and its tangential velocity
// component (unless a Dirichlet condition fixes it); slot j has the velocity c_j and the
// stress Lambda_j (p_nu = p(v_nu) + lambda_nu on a normal slot, lambda_tau on a tangential
// one). The solvers' unknown is m_j = Lambda_j - Kn_j c_j: Kn_j = p'(g) on normal slots is
// folded into the constant matrix S (an exact rewriting for any constant Kn_j).
//
// Resolvent form: for any r_j > 0 and y = Lambda + r c, the law picks one piece per slot
//   normal:     y <= 0                 Free    Lambda = 0
//               0 < y < p(g) + r g     Damped  Lambda = p(v), p(v) + r v = y, 0 < v < g
//               y >= p(g) + r g        Bound   original: v = g, Lambda = y - r g
//                                              penalty: Lambda = p(v) + (v - g)/eps, v >= g
//   tangential: s = mu p(c_partner), the bound of the node's normal slot (its "partner")
//               s > 0 and |y| <= s     Stick   Lambda = y (then v = 0)
//               otherwise              Slip    Lambda = s sign(y)
//   in 3D a node has two tangential slots (each the other's "pair"), the law is the disk's:
//   y_tau = (y_j, y_pair), |y_tau| its length, and Lambda_tau = proj_disk(s)(y_tau):
//               s > 0 and |y_tau| <= s Stick   Lambda_j = y_j (then v_tau = 0)
//               otherwise              Slip    Lambda_j = s y_j / |y_tau| (the friction force
//                                              colinear with the slip velocity)
//   (the pair shares its r: a projection with two r would turn the force off the slip)
// and the natural residual of slot j is |Lambda_j - target_j| (the Lambda the piece gives).
// A Newton step solves each slot's relation, the piece's equation linearized (p at the
// resolvent's v on Damped and Bound pieces, the friction bound at the partner's velocity on
// Slip, and on a disk's Slip the projection's derivative, its exact generalized Jacobian):
//   sum_t a_jt c[aSlot_jt] + sum_t d_jt m[dSlot_jt] = h_j,  t < termsPerRelation,
// one term of each in 2D (a_j c[slot_j] + d_j m_j = h_j), up to three c's and two m's on a
// disk's Slip. A piecewise-linear p makes them exact.
enum Piece { Free = 0, Damped = 1, Bound = 2, Stick = 3, Slip = 4 };

struct Slots {
  Parameters P;
  int n = 0;
  std::vector<char> normal;              // normal slot (else tangential)
  std::vector<int> partner;              // a tangential slot's normal slot, -1 if none
  std::vector<int> pair;                 // a tangential slot's other tangential slot (3D), -1 if none
  std::vector<double> g, Kn, r, forceScale, residualWeight;
  std::vector<double> velocityScale;     // per slot, |c_free|: the size of the terms c is computed from
  double roundoff = 0;                   // 10 u / tol (set with tol): see evaluate()
  // at the last evaluate(): piece, key, y, the resolvent's v (Damped, Bound) and target
  std::vector<int> piece, key;
  std::vector<double> stress, y, velocity, target, mismatch;
  // the relations of the pieces (relations()): slot j's terms at j * termsPerRelation + t
  static const int termsPerRelation = 3;
  std::vector<double> a, d, h;
  std::vector<int> aSlot, dSlot;

  void resize(int count) {
    n = count;
    normal.assign(n, 1); partner.assign(n, -1); pair.assign(n, -1);
    for (auto *v : {&g, &Kn, &r, &forceScale, &residualWeight, &velocityScale, &stress, &y, &velocity, &target, &mismatch, &h})
      v->assign(n, 0.);
    a.assign(termsPerRelation * n, 0.); d.assign(termsPerRelation * n, 0.);
    piece.assign(n, 0); key.assign(n, 0);
    aSlot.assign(termsPerRelation * n, 0); dSlot.assign(termsPerRelation * n, 0);
  }
  // the velocity bound and the force scale p(g) of slot j (a tangential slot: its node's)
  void setBound(int j, double bound) {
    g[j] = bound;
    forceScale[j] = contactlaw::forceScale(P, bound);
    Kn[j] = normal[j] ? dampedResponseSlope(P, bound) : 0.;
  }
  // the augmentation of slot j, and the weight of its residual: stress mismatches relative
  // to p(g), and the velocity mismatch they imply (|.|/r) relative to g
  void setAugmentation(int j, double rj) {
    r[j] = rj;
    residualWeight[j] = std::max(1. / forceScale[j], 1. / (rj * g[j]));
  }

  // v with p(base + v) - p(base) + s v = b on [0, hi] (a nondecreasing p, s > 0, b >= 0):
  // Newton's method, kept inside a bracket by bisection
  double solveResolvent(double base, double s, double b, double hi, double start) const {
    const double pBase = dampedResponse(P, base);
    double lo = 0, v = std::min(std::max(start, lo), hi);
    for (int k = 0; k < 100; k++) {
      const double f = dampedResponse(P, base + v) - pBase + s * v - b;
      if (f == 0) return v;
      if (f > 0) hi = v; else lo = v;
      const double slope = dampedResponseSlope(P, base + v) + s;
      double next = v - f / slope;
      if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);
      if (std::fabs(next - v) <= 1e-15 * std::fabs(v) || hi - lo <= 1e-15 * hi) return next;
      v = next;
    }
    return v;
  }

  // The piece of slot j at yj = Lambda_j + rj c_j, for any rj > 0: returns the piece, sets t to the
  // stress it gives and v to the resolvent's velocity (Damped and Bound pieces; else unchanged).
  // c: the slot velocities (a tangential slot reads its partner's); yPair: y of the slot's
  // pair (3D). Every solver goes through here: Newton with its r_j (evaluate below), the fixed
  // point with each slot's exact local r (a 3D pair's: diskUpdate() below).
  int resolve(int j, double yj, double rj, const double *c, double &t, double &v, double yPair = 0) const {
    if (normal[j]) {
      const double pg = dampedResponse(P, g[j]);
      if (yj <= 0) { t = 0.; return Free; }
      if (yj < pg + rj * g[j]) {
        const double slope = dampedResponseSlope(P, g[j]);      // exact start for a linear p
        v = solveResolvent(0., rj, yj, g[j], yj / (slope + rj));
        t = dampedResponse(P, v);
        return Damped;
      }
      if (!P.penalty) { v = g[j]; t = yj - rj * g[j]; return Bound; }
      const double s = 1. / P.eps + rj, b = yj - rj * g[j] - pg;  // penalty: v = g + overshoot
      const double slope = dampedResponseSlope(P, g[j]);
      const double over = solveResolvent(g[j], s, b, b / s, b / (slope + s));
      v = g[j] + over;
      t = (yj - rj * g[j]) - rj * over;
      return Bound;
    }
    const double s = partner[j] >= 0 ? frictionBound(P, c[partner[j]]) : 0.;
    if (pair[j] >= 0) {                                                  // the disk
      const double length = std::hypot(yj, yPair);
      t = length <= s ? yj : (length > 0 ? s * yj / length : 0.);
      return (s > 0 && length <= s) ? Stick : Slip;
    }
    t = std::max(-s, std::min(s, yj));
    return (s > 0 && std::fabs(yj) <= s) ? Stick : Slip;
  }

  // pieces, targets and the weighted natural residual (max norm; NaN if any is NaN) at (c, m).
  // A slot's mismatch Lambda - target is weighted by residualWeight, unless its terms are so
  // large (a body moving at many times g, a free flight, r c at a large r, with c computed
  // from velocities of size velocityScale) that their round-off would exceed tol: then
  // relative to the terms, so that round-off reads tol/10 at most.
  double evaluate(const double *c, const double *m) {
    double worst = 0;
    for (int j = 0; j < n; j++) {
      stress[j] = Kn[j] * c[j] + m[j];
      y[j] = stress[j] + r[j] * c[j];
    }
    for (int j = 0; j < n; j++) {
      const double lambda = stress[j], yj = y[j];
      double t = 0;
      const int p = resolve(j, yj, r[j], c, t, velocity[j], pair[j] >= 0 ? y[pair[j]] : 0.);
      // a slip piece's key: the side of y, and whether the bound s is positive (t = +-s)
      key[j] = 4 * p + (p == Slip ? 2 * (yj > 0) + (t != 0) : 0);
      piece[j] = p;
      target[j] = t;
      double weight = residualWeight[j];
      double terms = std::fabs(Kn[j] * c[j]) + std::fabs(m[j]) + r[j] * (std::fabs(c[j]) + velocityScale[j]);
      if (!normal[j] && partner[j] >= 0)                  // a slip's target mu p(c_nu): the round-off of c_nu through p'
        terms += std::fabs(frictionBoundSlope(P, c[partner[j]])) * (std::fabs(c[partner[j]]) + velocityScale[partner[j]]);
      terms *= roundoff;
      if (terms * weight > 1) weight = 1 / terms;
      mismatch[j] = (lambda - t) * weight;
      worst = std::max(worst, std::fabs(mismatch[j]));
      if (std::isnan(mismatch[j])) worst = mismatch[j];
    }
    return worst;
  }
  // Slots whose piece fixes their velocity (stick: v_tau = 0; at the bound, original problem:
  // v_nu = g) but whose velocity the statuses above would read otherwise: a natural residual
  // below a loose tol still lets a sticking node slip at up to tol g, above the stick
  // threshold. A step has converged only when there is none, so that contact.txt and the
  // zones report the pieces the solver found (at the last evaluate()).
  // (Up to the round-off of c itself, 10 u (|c| + |c_free|): a bound far below that cannot be
  // resolved, and the end-of-run checks judge such a run.)
  int unresolvedStatuses(const double *c) const {
    int count = 0;
    for (int j = 0; j < n; j++) {
      const double slack = 10 * DBL_EPSILON * (std::fabs(c[j]) + velocityScale[j]);
      const double inward = c[j] > 0 ? c[j] - slack : c[j] + slack;    // c moved by its round-off toward 0
      if (piece[j] == Stick && pair[j] >= 0) {                         // the disk: the length of v_tau
        const double other = c[pair[j]], otherSlack = 10 * DBL_EPSILON * (std::fabs(other) + velocityScale[pair[j]]);
        const double length = std::hypot(std::max(std::fabs(c[j]) - slack, 0.), std::max(std::fabs(other) - otherSlack, 0.));
        if (tangentialStatus(length, g[j]) != 0) count++;
        continue;
      }
      if (piece[j] == Stick && tangentialStatus(std::fabs(c[j]) <= slack ? 0. : inward, g[j]) != 0) count++;
      if (piece[j] == Bound && !P.penalty && normalStatus(c[j] + slack, g[j]) != 2) count++;
    }
    return count;
  }
  // The fixed point's exact update of a 3D node's tangential pair (j, q = pair[j]), with the
  // pair's 2x2 block D = [Djj Djq; Dqj Dqq] of Dw and the other slots held: c_tau = b - D m_tau
  // (b = c_tau + D m_tau at the current iterate), and the disk law asks for b - D m in the
  // normal cone of the disk |m| <= s at m, s = mu p(c_partner): the minimum of m'Dm/2 - b'm on
  // the disk. Stick when |D^-1 b| <= s: m = D^-1 b. Else the projection of D^-1 b on the disk
  // under the metric D, m = (D + nu I)^-1 b with nu > 0 such that |m| = s (Newton on
  // 1/|m(nu)| - 1/s, kept in its bracket by bisection). Exact, as resolve() is for a scalar
  // slot. Sets (mj, mq).
  void diskUpdate(int j, double Djj, double Djq, double Dqj, double Dqq, double bj, double bq, const double *c,
                  double &mj, double &mq) const {
    const int p = partner[j];
    const double s = p >= 0 ? frictionBound(P, c[p]) : 0.;
    mj = 0; mq = 0;
    auto solveShifted = [&](double nu, double &xj, double &xq) {   // (D + nu I) x = b
      const double a11 = Djj + nu, a22 = Dqq + nu, det = a11 * a22 - Djq * Dqj;
      xj = (a22 * bj - Djq * bq) / det; xq = (a11 * bq - Dqj * bj) / det;
    };
    if (!(s > 0)) return;
    solveShifted(0., mj, mq);
    const double bLength = std::hypot(bj, bq);
    if (!(std::hypot(mj, mq) > s)) return;                          // stick: D^-1 b is on the disk
    double lo = 0, hi = bLength / s, nu = 0;
    for (int k = 0; k < 100; k++) {
      double xj, xq;
      solveShifted(nu, xj, xq);
      const double length = std::hypot(xj, xq), psi = 1 / length - 1 / s;
      if (psi < 0) lo = nu; else hi = nu;
      // psi'(nu) = x'(D + nu I)^-1 x / |x|^3
      double yj, yq;
      { const double a11 = Djj + nu, a22 = Dqq + nu, det = a11 * a22 - Djq * Dqj;
        yj = (a22 * xj - Djq * xq) / det; yq = (a11 * xq - Dqj * xj) / det; }
      const double slope = (xj * yj + xq * yq) / (length * length * length);
      double next = nu - psi / slope;
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::fabs(psi) * s <= 1e-15 || hi - lo <= 1e-15 * hi) { mj = xj; mq = xq; break; }
      nu = next;
      mj = xj; mq = xq;
    }
    const double length = std::hypot(mj, mq);                       // on the circle exactly
    if (length > 0) { mj *= s / length; mq *= s / length; }
  }
  bool hasPairs() const { return std::any_of(pair.begin(), pair.end(), [](int q) { return q >= 0; }); }   // 3D disks
  double merit() const {
    double s = 0;
    for (int j = 0; j < n; j++) s += mismatch[j] * mismatch[j];
    return std::sqrt(s);
  }

  // the relations of each slot's piece, at the last evaluate()
  void relations(const double *c) {
    const int T = termsPerRelation;
    for (int j = 0; j < n; j++) {
      for (int t = 1; t < T; t++) { a[T * j + t] = 0; d[T * j + t] = 0; aSlot[T * j + t] = j; dSlot[T * j + t] = j; }
      if (piece[j] == Slip && pair[j] >= 0) { diskSlip(j, c); continue; }
      double aj = 0, dj = 1, hj = 0;
      int sj = j;
      const double v = velocity[j];
      switch (piece[j]) {
        case Free: aj = Kn[j]; break;                                     // Lambda = 0
        case Damped: {                                                    // Lambda = p(v) + p'(v)(c - v)
          const double slope = dampedResponseSlope(P, v);
          aj = Kn[j] - slope; hj = dampedResponse(P, v) - slope * v;
          break;
        }
        case Bound:
          if (!P.penalty) { aj = 1; dj = 0; hj = g[j]; }                  // c = g
          else {                                                          // Lambda = p(c) + (c - g)/eps, linearized at v
            const double slope = dampedResponseSlope(P, v), offset = dampedResponse(P, v) - slope * v;
            if (P.literal) { aj = Kn[j] - slope - 1. / P.eps; hj = offset - g[j] / P.eps; }
            else { aj = 1 + P.eps * (slope - Kn[j]); dj = -P.eps; hj = g[j] - P.eps * offset; }
          }
          break;
        case Stick: aj = 1; dj = 0; break;                                // c = 0
        case Slip:                                                        // Lambda = sign(y) F(c_partner), linearized
          if (partner[j] >= 0) {
            const double sign = y[j] > 0 ? 1. : -1., cp = c[partner[j]];
            const double slope = frictionBoundSlope(P, cp);
            sj = partner[j]; aj = -sign * slope; hj = sign * (frictionBound(P, cp) - slope * cp);
          }
          break;
      }
      a[T * j] = aj; d[T * j] = dj; h[j] = hj; aSlot[T * j] = sj; dSlot[T * j] = j;
    }
  }
  // A disk's Slip, Lambda_tau = s(c_p) y/|y| with y = m_tau + r c_tau (Kn = 0 on tangential
  // slots), linearized: with e = y/|y| and Pr = s/|y| (I - e e'), the derivative of the
  // projection, row j of  (I - Pr) m_tau - r Pr c_tau - e s'(c_p) c_p = e (s - s'(c_p) c_p)
  // (its right-hand side: (I - Pr) m - r Pr c = m - Pr y = m, as Pr y = 0).
  void diskSlip(int j, const double *c) {
    const int T = termsPerRelation, q = pair[j], p = partner[j];
    const double length = std::hypot(y[j], y[q]);
    const double cp = p >= 0 ? c[p] : 0., s = p >= 0 ? frictionBound(P, cp) : 0.;
    const double slope = p >= 0 ? frictionBoundSlope(P, cp) : 0.;
    const double ej = length > 0 ? y[j] / length : 0., eq = length > 0 ? y[q] / length : 0.;
    const double scale = length > 0 ? s / length : 0.;
    const double Pjj = scale * (1 - ej * ej), Pjq = -scale * ej * eq;
    d[T * j] = 1 - Pjj; dSlot[T * j] = j;
    d[T * j + 1] = -Pjq; dSlot[T * j + 1] = q;
    a[T * j] = -r[j] * Pjj; aSlot[T * j] = j;
    a[T * j + 1] = -r[j] * Pjq; aSlot[T * j + 1] = q;
    a[T * j + 2] = p >= 0 ? -ej * slope : 0.; aSlot[T * j + 2] = p >= 0 ? p : j;
    h[j] = ej * (s - slope * cp);
  }
};

// The zones' names are the outputs' column names zone_NAME: each a word of lowercase letters,
// digits and '_', all different. "" if so, else why not (checkLaw; the scripts ask first,
// contactKernelZoneProblem, before they name the columns).
inline std::string zoneNamesProblem() {
  for (int z = 0; z < zoneCount; z++) {
    const std::string name = zoneNames[z], index = std::to_string(z);
    if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
      return "zoneNames[" + index + "] = '" + name + "' is not a name of lowercase letters, digits and '_'";
    for (int y = 0; y < z; y++)
      if (name == zoneNames[y]) return "zoneNames[" + std::to_string(y) + "] and zoneNames[" + index + "] are both '" + name + "'";
  }
  return "";
}

// Is the law above one the solvers can use? 0 if so; otherwise 1 and a sentence in why.
// Checked when a run starts, on 73 points r = k g/8 of [-g, 8g] (the range a run's velocities reach;
// a law can only be sampled): p(r) = p'(r) = 0 for r <= 0; p finite and nondecreasing; the
// friction bound finite and >= 0; each slope equal to the difference quotient on its left,
// its right or across r (a kink at r takes the slope on its left); the statuses and zones in
// their ranges, the zones' names words of their own; the force scale p(g) 0 or at least 1e-150 (the residual weighs a stress by
// 1/p(g), Slots::setAugmentation).
inline int checkLaw(const Parameters &P, double g, std::string &why) {
  auto text = lawNumber;
  const double h = 1e-7 * g;
  if (!(h > 0 && std::isfinite(8 * g))) { why = "g = " + text(g) + " is too small or too large to sample the law"; return 1; }
  const double pg = dampedResponse(P, g);
  if (!std::isfinite(pg)) { why = "p is not finite at the bound: p(g) = " + text(pg); return 1; }   // (the scales below divide by it)
  if (pg > 0 && pg < 1e-150) {
    why = "p(g) = " + text(pg) + " is above 0 but below 1e-150: the residual weighs the stresses by 1/p(g)";
    return 1;
  }
  // |slope - difference quotient of f at r| small on one side or across r
  auto matches = [h](double (*f)(const Parameters &, double), const Parameters &P, double r, double slope, double scale) {
    const double left = (f(P, r) - f(P, r - h)) / h, right = (f(P, r + h) - f(P, r)) / h;
    const double across = (f(P, r + h) - f(P, r - h)) / (2 * h);
    for (double q : {left, right, across})
      if (std::fabs(slope - q) <= 1e-4 * (std::fabs(q) + scale)) return true;
    return false;
  };
  const double pScale = std::max(std::fabs(dampedResponse(P, g)) / g, 1e-300);
  const double fScale = std::max(std::fabs(frictionBound(P, g)) / g, 1e-300);
  double previous = 0;
  for (int k = -8; k <= 64; k++) {
    const double r = g * k / 8.;
    const double p = dampedResponse(P, r), slope = dampedResponseSlope(P, r);
    const double F = frictionBound(P, r), Fslope = frictionBoundSlope(P, r);
    if (k <= 0 && (p != 0 || slope != 0)) { why = "p(r) or p'(r) is not 0 at r = " + text(r) + " <= 0"; return 1; }
    if (!std::isfinite(p) || !std::isfinite(slope) || p < previous || slope < 0) {
      why = "p is not finite and nondecreasing at r = " + text(r);
      return 1;
    }
    if (!std::isfinite(F) || !std::isfinite(Fslope) || F < 0) {
      why = "the friction bound is not finite and >= 0 at v_nu = " + text(r);
      return 1;
    }
    if (k > 0 && !matches(dampedResponse, P, r, slope, pScale)) {
      why = "p'(" + text(r) + ") = " + text(slope) + " but the difference quotient of p there is "
            + text((dampedResponse(P, r + h) - dampedResponse(P, r - h)) / (2 * h));
      return 1;
    }
    if (!matches(frictionBound, P, r, Fslope, fScale)) {
      why = "frictionBoundSlope(" + text(r) + ") = " + text(Fslope) + " but the difference quotient of frictionBound there is "
            + text((frictionBound(P, r + h) - frictionBound(P, r - h)) / (2 * h));
      return 1;
    }
    previous = p;
    const int normal = normalStatus(r, g), tangential = tangentialStatus(r - g, g);
    if (normal < 0 || normal > 2 || tangential < 0 || tangential > 1) {
      why = "a status is out of its range at v = " + text(r) + " (normal 0..2, tangential 0..1)";
      return 1;
    }
  }
  why = zoneNamesProblem();
  if (!why.empty()) return 1;
  for (int normal = 0; normal <= 2; normal++)
    for (int tangential = 0; tangential <= 1; tangential++)
      if (zone(normal, tangential) < 0 || zone(normal, tangential) >= zoneCount) {
        why = "zone(" + text(normal) + ", " + text(tangential) + ") is not a zone 0.." + text(zoneCount - 1);
        return 1;
      }
  return 0;
}

// Is the bound above, velocityBound with the scene's bound_profile or bound_table, one the
// solvers can use over the whole of Gamma3? 0 if so (and with -g alone: checkLaw then runs at
// each node's g); otherwise 1 and a sentence in why. Checked when a run starts, on the grid of
// the profile (its points x_k) or of the table (its points (a_i, b_j)): at each point, g is that
// point's value; at the middle of each segment or cell, g lies between the values around it (so
// g between its points stays within the range the points give, wherever a node lies); each g
// finite and > 0; and checkLaw at each point's g (the bound's extremes are among them).
inline int checkBound(const Parameters &P, std::string &why) {
  const bool table = !P.tableG.empty();
  const std::vector<double> &A = table ? P.tableA : P.profileX, &G = table ? P.tableG : P.profileG;
  if (G.empty()) return 0;
  const int axisA = table ? P.tableAxisA : 0, axisB = table ? P.tableAxisB : 1;
  const char *const axes = "xyz";
  const size_t N = A.size(), M = table ? P.tableB.size() : 1;   // (a profile: one line along B)
  auto lineB = [&](size_t j) { return table ? P.tableB[j] : 0.; };
  for (size_t i = 0; i + 1 < 2 * N; i++)           // even: a point, odd: the middle of a segment
    for (size_t j = 0; j + 1 < 2 * M; j++) {
      const size_t i0 = i / 2, i1 = (i + 1) / 2, j0 = j / 2, j1 = (j + 1) / 2;
      double position[3] = {0, 0, 0};
      position[axisA] = 0.5 * A[i0] + 0.5 * A[i1];
      position[axisB] = 0.5 * lineB(j0) + 0.5 * lineB(j1);
      const double around[4] = {G[i0 * M + j0], G[i0 * M + j1], G[i1 * M + j0], G[i1 * M + j1]};
      const double lo = *std::min_element(around, around + 4), hi = *std::max_element(around, around + 4);
      const bool point = i0 == i1 && j0 == j1;
      auto where = [&]() {                           // (only for a message)
        return std::string(table ? "the bound_table's " : "the bound_profile's ") + (point ? "point " : "middle ")
               + (table ? std::string("(") + axes[axisA] + ", " + axes[axisB] + ") = (" + lawNumber(position[axisA]) + ", "
                          + lawNumber(position[axisB]) + ")"
                        : "x = " + lawNumber(position[0]));
      };
      const double g = velocityBound(P, position);
      if (!(std::isfinite(g) && g > 0 && (point ? g == lo : (g >= lo && g <= hi)))) {
        why = "velocityBound gives g = " + lawNumber(g) + " at " + where() + (point ? ", whose value is " + lawNumber(lo)
              : ", between points of values " + lawNumber(lo) + " to " + lawNumber(hi)) + " (g must be finite, > 0, and between its points)";
        return 1;
      }
      if (point && checkLaw(P, g, why)) { why += "; at " + where() + ", g = " + lawNumber(g); return 1; }
    }
  return 0;
}

}  // namespace contactlaw
#endif
