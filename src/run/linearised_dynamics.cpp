#include "src/run/linearised_dynamics.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "src/base/symmetric_eigen.h"

namespace kiln {

namespace {

constexpr int stiff_modes = 24, damped_modes = 8;
enum Spring { normal_spring, tangential_spring, rolling_spring };
constexpr const char* spring_kind[] = {"normal", "tangential-rotational", "rolling"};

double stiffness(const ContactSprings& s, int kind) {
  return kind == normal_spring ? s.kn : kind == tangential_spring ? s.kt : s.kr;
}
double dashpot(const ContactSprings& s, int kind) {
  return kind == normal_spring ? s.cn : kind == tangential_spring ? s.ct : s.cr;
}

// Orthonormalises q's columns in place (Gram-Schmidt, twice: kept orthogonal), dropping those
// already (nearly) in the span of the ones before.
void orthonormalise(Eigen::MatrixXd& q) {
  Eigen::Index kept = 0;
  for (Eigen::Index c = 0; c < q.cols(); ++c) {
    Eigen::VectorXd v = q.col(c);
    for (int pass = 0; pass < 2; ++pass) v -= q.leftCols(kept) * (q.leftCols(kept).transpose() * v);
    const double size = v.norm();
    if (size < 1e-8) continue;
    q.col(kept++) = v / size;
  }
  q.conservativeResize(Eigen::NoChange, kept);
}

// K~ (the springs) or C~ (the dashpots) applied from the rows: each spring adds
// coefficient B^T (B x); a wall body's dashpot adds to its diagonal.
class SpringOperator final : public SymmetricOperator {
 public:
  SpringOperator(const LinearisedMechanics& m, bool dashpots, std::vector<std::pair<int, double>> diagonal)
      : m_(m), dashpots_(dashpots), diagonal_(std::move(diagonal)) {}
  int rows() const override { return m_.coordinates; }
  double coefficient(size_t contact, int kind) const {
    return dashpots_ ? dashpot(m_.contacts[contact], kind) : stiffness(m_.contacts[contact], kind);
  }
  bool zero() const {
    for (size_t p = 0; p < m_.contacts.size(); ++p)
      for (int kind : {normal_spring, tangential_spring, rolling_spring})
        if (coefficient(p, kind) != 0 && m_.rows[p][kind].size > 0) return false;
    return diagonal_.empty();
  }
  void apply(const double* x, double* y) const override {
    std::fill_n(y, rows(), 0.0);
    for (const auto& [at, d] : diagonal_) y[at] += d * x[at];
    for (size_t p = 0; p < m_.contacts.size(); ++p)
      for (int kind : {normal_spring, tangential_spring, rolling_spring}) {
        const double k = coefficient(p, kind);
        if (k == 0) continue;
        const SpringRow& r = m_.rows[p][kind];
        double strain = 0;
        for (int a = 0; a < r.size; ++a) strain += r.by[a] * x[r.at[a]];
        for (int a = 0; a < r.size; ++a) y[r.at[a]] += k * strain * r.by[a];
      }
  }

 private:
  const LinearisedMechanics& m_;
  bool dashpots_;
  std::vector<std::pair<int, double>> diagonal_;
};

// The `count` largest eigenpairs of `a` that strain it: a free body's rigid motion (eigenvalue 0
// of both operators) binds no step and is left out.
Eigenpairs straining_modes(const SpringOperator& a, int count) {
  if (a.zero()) return {};
  Eigenpairs e = largest_eigenpairs(a, count);
  // A spring beyond double precision (epsd rolling friction 1e300: k_r = 2.25 k_n mu_r^2 R*^2 is
  // infinite) gives values that are no numbers: kept, so that the limit is NaN and refused; the
  // test below dropped them all, and the contact's mode with them.
  if (e.values.size() && !std::isfinite(e.values[0])) return e;
  Eigen::Index kept = 0;
  while (kept < e.values.size() && e.values[kept] > 1e-9 * e.values[0]) ++kept;
  e.values.conservativeResize(kept);
  e.vectors.conservativeResize(Eigen::NoChange, kept);
  return e;
}

// basis^T a basis, exactly symmetric as the operator is: one product per column.
Eigen::MatrixXd projected(const SpringOperator& a, const Eigen::MatrixXd& basis) {
  Eigen::MatrixXd p(basis.cols(), basis.cols());
  Eigen::VectorXd column(basis.rows());
  for (Eigen::Index c = 0; c < basis.cols(); ++c) {
    a.apply(basis.col(c).data(), column.data());
    p.col(c) = basis.transpose() * column;
  }
  return 0.5 * (p + p.transpose());
}

}  // namespace

LinearisedMechanics linearise_mechanics(const DemSystem& sys, double t, const double* y, Springs springs) {
  LinearisedMechanics m;
  const Scene& scene = sys.scene();
  m.contacts = sys.contact_springs(t, y);
  if (springs == Springs::uncapped)
    for (ContactSprings& s : m.contacts) s.kt = s.ct = s.kr = s.cr = 0;
  const bool rotates = sys.rotates();
  std::vector<int> particle_at;        // each particle's first coordinate, -1 when it has none
  std::vector<double> inv_sqrt_mass;   // per coordinate: 1/sqrt(kg), or 1/sqrt(kg m^2) for an angle
  int n = 0;
  for (int i = 0; i < sys.particles(); ++i) {
    particle_at.push_back(sys.attached(i) ? -1 : n);
    if (sys.attached(i)) continue;
    inv_sqrt_mass.insert(inv_sqrt_mass.end(), 2, 1 / std::sqrt(sys.mass(i)));
    if (rotates) inv_sqrt_mass.push_back(1 / std::sqrt(sys.inertia(i)));
    n += rotates ? 3 : 2;
  }
  std::vector<std::pair<int, double>> body_dashpots;
  std::vector<Vec2> load(sys.bodies());  // unit directions of the bodies' coordinates
  for (size_t w = 0; w < scene.walls.size(); ++w) {
    const int b = sys.body_of_wall(static_cast<int>(w));
    if (b < 0) continue;
    const WallMotion& motion = scene.walls[w].motion;
    m.body_at.resize(std::max<size_t>(m.body_at.size(), b + 1));
    m.body_at[b] = n;
    load[b] = motion.along_load(1);
    inv_sqrt_mass.push_back(1 / std::sqrt(motion.mass));
    if (motion.damping > 0) body_dashpots.emplace_back(n, motion.damping / motion.mass);
    ++n;
  }
  m.coordinates = n;
  auto term = [&](SpringRow& r, int coordinate, double coefficient) {
    r.add(coordinate, coefficient * inv_sqrt_mass[coordinate]);
  };
  // A body's displacement along `dir` (+1 for i, -1 for the other): its own coordinates, those of
  // the wall body it is attached to, or none (driven).
  auto translation = [&](SpringRow& r, int i, double sign, Vec2 dir) {
    if (particle_at[i] >= 0) {
      term(r, particle_at[i], sign * dir.x);
      term(r, particle_at[i] + 1, sign * dir.y);
    } else if (const int w = scene.attached[i]; w >= 0 && sys.body_of_wall(w) >= 0) {
      term(r, m.body_at[sys.body_of_wall(w)], sign * dot(dir, load[sys.body_of_wall(w)]));
    }
  };
  auto angle = [&](SpringRow& r, int i, double coefficient) {
    if (rotates && particle_at[i] >= 0) term(r, particle_at[i] + 2, coefficient);
  };
  m.rows.reserve(m.contacts.size());
  for (const ContactSprings& s : m.contacts) {
    std::array<SpringRow, 3> rows;
    const Vec2 n_dir = s.normal, t_dir = perp(s.normal);
    const int wall_body = s.j < 0 ? sys.body_of_wall(-1 - s.j) : -1;
    for (int kind : {normal_spring, tangential_spring}) {
      const Vec2 dir = kind == normal_spring ? n_dir : t_dir;
      translation(rows[kind], s.i, 1, dir);
      if (s.j >= 0) translation(rows[kind], s.j, -1, dir);
      if (wall_body >= 0) term(rows[kind], m.body_at[wall_body], -dot(dir, load[wall_body]));
    }
    angle(rows[tangential_spring], s.i, s.arm_i);
    angle(rows[rolling_spring], s.i, 1);
    if (s.j >= 0) {
      angle(rows[tangential_spring], s.j, s.arm_j);
      angle(rows[rolling_spring], s.j, -1);
    }
    m.rows.push_back(rows);
  }
  const SpringOperator ks(m, false, {}), cs(m, true, std::move(body_dashpots));
  // The directions that strain a spring or a dashpot, one after the other: only one Lanczos basis
  // exists at a time.
  {
    Eigenpairs stiff = straining_modes(ks, stiff_modes);
    m.omega_max = stiff.values.size() ? std::sqrt(std::max(0.0, stiff.values[0])) : 0.0;
    const Eigenpairs damped = straining_modes(cs, damped_modes);
    const Eigen::Index a = stiff.values.size(), b = damped.values.size();
    m.basis.resize(n, a + b);
    if (a) m.basis.leftCols(a) = stiff.vectors;
    if (b) m.basis.rightCols(b) = damped.vectors;
  }
  orthonormalise(m.basis);
  m.k = projected(ks, m.basis);
  m.c = projected(cs, m.basis);
  return m;
}

ModeDescription describe_mode(const LinearisedMechanics& m, const Eigen::VectorXcd& reduced_shape, const Scene& scene) {
  ModeDescription d;
  if (reduced_shape.size() != m.basis.cols() || m.basis.cols() == 0) return d;
  Eigen::VectorXcd scaled(m.basis.rows());  // real and imaginary parts apart: no complex copy of the basis
  scaled.real() = m.basis * reduced_shape.real();
  scaled.imag() = m.basis * reduced_shape.imag();
  // The wall bodies' share of the kinetic energy (|amplitude|^2 in mass-scaled coordinates).
  double bodies = 0;
  int heaviest = -1;
  for (size_t b = 0; b < m.body_at.size(); ++b) {
    bodies += std::norm(scaled[m.body_at[b]]);
    if (heaviest < 0 || std::norm(scaled[m.body_at[b]]) > std::norm(scaled[m.body_at[heaviest]]))
      heaviest = static_cast<int>(b);
  }
  if (bodies > 0.5 * scaled.squaredNorm()) {
    d.kind = "wall body";
    int b = 0;
    for (const Wall& w : scene.walls)
      if (w.motion.free_along_load() && b++ == heaviest) d.where = "wall " + w.name;
    return d;
  }
  // Each spring's energy k |B u|^2 (a mode no spring holds: its dashpots' c |B u|^2), B u from the
  // mass-scaled rows and shape.
  auto energies = [&](bool springs) {
    double total[3] = {0, 0, 0}, best = -1;
    int best_kind = 0, best_contact = -1;
    std::vector<std::array<double, 3>> each(m.contacts.size());
    for (size_t p = 0; p < m.contacts.size(); ++p)
      for (int kind = 0; kind < 3; ++kind) {
        const SpringRow& r = m.rows[p][kind];
        std::complex<double> strain = 0;
        for (int a = 0; a < r.size; ++a) strain += r.by[a] * scaled[r.at[a]];
        const double coefficient = springs ? stiffness(m.contacts[p], kind) : dashpot(m.contacts[p], kind);
        each[p][kind] = coefficient * std::norm(strain);
        total[kind] += each[p][kind];
      }
    for (int kind = 0; kind < 3; ++kind)
      if (total[kind] > best) {
        best = total[kind];
        best_kind = kind;
      }
    double most = 0;
    for (size_t p = 0; p < m.contacts.size(); ++p)
      if (each[p][best_kind] > most) {
        most = each[p][best_kind];
        best_contact = static_cast<int>(p);
      }
    return std::make_pair(best > 0 ? best_kind : -1, best_contact);
  };
  auto [kind, contact] = energies(true);
  if (kind < 0) std::tie(kind, contact) = energies(false);
  if (kind < 0 || contact < 0) return d;
  d.kind = spring_kind[kind];
  const ContactSprings& s = m.contacts[contact];
  d.where = s.j >= 0 ? "particles " + std::to_string(s.i) + " and " + std::to_string(s.j)
                     : "particle " + std::to_string(s.i) + " on wall " + scene.walls[-1 - s.j].name;
  return d;
}

}  // namespace kiln
