#include "src/run/linearised_dynamics.h"

#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>

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

// Orthonormal columns spanning `columns`, dropping those already (nearly) in the span.
Eigen::MatrixXd orthonormal(const Eigen::MatrixXd& columns) {
  Eigen::MatrixXd q(columns.rows(), 0);
  for (Eigen::Index c = 0; c < columns.cols(); ++c) {
    Eigen::VectorXd v = columns.col(c);
    for (int pass = 0; pass < 2; ++pass) v -= q * (q.transpose() * v);  // twice: kept orthogonal
    const double size = v.norm();
    if (size < 1e-8) continue;
    q.conservativeResize(Eigen::NoChange, q.cols() + 1);
    q.col(q.cols() - 1) = v / size;
  }
  return q;
}

}  // namespace

LinearisedMechanics linearise_mechanics(const DemSystem& sys, double t, const double* y, Springs springs) {
  LinearisedMechanics m;
  const Scene& scene = sys.scene();
  m.contacts = sys.contact_springs(t, y);
  if (springs == Springs::uncapped)
    for (ContactSprings& s : m.contacts) s.kt = s.ct = s.kr = s.cr = 0;
  const bool rotates = sys.rotates();
  std::vector<int> particle_at;  // each particle's first coordinate, -1 when it has none
  int n = 0;
  for (int i = 0; i < sys.particles(); ++i) {
    particle_at.push_back(sys.attached(i) ? -1 : n);
    if (sys.attached(i)) continue;
    m.inv_sqrt_mass.insert(m.inv_sqrt_mass.end(), 2, 1 / std::sqrt(sys.mass(i)));
    if (rotates) m.inv_sqrt_mass.push_back(1 / std::sqrt(sys.inertia(i)));
    n += rotates ? 3 : 2;
  }
  std::vector<Eigen::Triplet<double>> kt, ct;
  std::vector<Vec2> load(sys.bodies());  // unit directions of the bodies' coordinates
  for (size_t w = 0; w < scene.walls.size(); ++w) {
    const int b = sys.body_of_wall(static_cast<int>(w));
    if (b < 0) continue;
    const WallMotion& motion = scene.walls[w].motion;
    m.body_at.resize(std::max<size_t>(m.body_at.size(), b + 1));
    m.body_at[b] = n;
    load[b] = motion.along_load(1);
    m.inv_sqrt_mass.push_back(1 / std::sqrt(motion.mass));
    if (motion.damping > 0) ct.emplace_back(n, n, motion.damping / motion.mass);
    ++n;
  }
  m.coordinates = n;
  // A body's displacement along `dir` (+1 for i, -1 for the other): its own coordinates, those of
  // the wall body it is attached to, or none (driven).
  auto translation = [&](SpringRow& r, int i, double sign, Vec2 dir) {
    if (particle_at[i] >= 0) {
      r.add(particle_at[i], sign * dir.x);
      r.add(particle_at[i] + 1, sign * dir.y);
    } else if (const int w = scene.attached[i]; w >= 0 && sys.body_of_wall(w) >= 0) {
      r.add(m.body_at[sys.body_of_wall(w)], sign * dot(dir, load[sys.body_of_wall(w)]));
    }
  };
  auto angle = [&](SpringRow& r, int i, double coefficient) {
    if (rotates && particle_at[i] >= 0) r.add(particle_at[i] + 2, coefficient);
  };
  for (const ContactSprings& s : m.contacts) {
    std::array<SpringRow, 3> rows;
    const Vec2 n_dir = s.normal, t_dir = perp(s.normal);
    const int wall_body = s.j < 0 ? sys.body_of_wall(-1 - s.j) : -1;
    for (int kind : {normal_spring, tangential_spring}) {
      const Vec2 dir = kind == normal_spring ? n_dir : t_dir;
      translation(rows[kind], s.i, 1, dir);
      if (s.j >= 0) translation(rows[kind], s.j, -1, dir);
      if (wall_body >= 0) rows[kind].add(m.body_at[wall_body], -dot(dir, load[wall_body]));
    }
    angle(rows[tangential_spring], s.i, s.arm_i);
    angle(rows[rolling_spring], s.i, 1);
    if (s.j >= 0) {
      angle(rows[tangential_spring], s.j, s.arm_j);
      angle(rows[rolling_spring], s.j, -1);
    }
    for (int kind : {normal_spring, tangential_spring, rolling_spring}) {
      const double k = stiffness(s, kind), c = dashpot(s, kind);
      const SpringRow& r = rows[kind];
      for (int a = 0; a < r.size; ++a)
        for (int b = 0; b < r.size; ++b) {
          const double scaled = r.by[a] * r.by[b] * m.inv_sqrt_mass[r.at[a]] * m.inv_sqrt_mass[r.at[b]];
          if (k != 0) kt.emplace_back(r.at[a], r.at[b], k * scaled);
          if (c != 0) ct.emplace_back(r.at[a], r.at[b], c * scaled);
        }
    }
    m.rows.push_back(rows);
  }
  Eigen::SparseMatrix<double> ks(n, n), cs(n, n);
  ks.setFromTriplets(kt.begin(), kt.end());
  cs.setFromTriplets(ct.begin(), ct.end());
  // The directions that strain a spring or a dashpot; a free body's rigid motion (eigenvalue 0
  // of both) binds no step and is left out.
  Eigen::MatrixXd columns(n, 0);
  auto keep = [&](const Eigen::SparseMatrix<double>& a, int count) {
    if (a.nonZeros() == 0) return 0.0;
    const Eigenpairs e = largest_eigenpairs(a, count);
    for (Eigen::Index c = 0; c < e.values.size() && e.values[c] > 1e-9 * e.values[0]; ++c) {
      columns.conservativeResize(Eigen::NoChange, columns.cols() + 1);
      columns.col(columns.cols() - 1) = e.vectors.col(c);
    }
    return e.values.size() ? std::max(0.0, e.values[0]) : 0.0;
  };
  m.omega_max = std::sqrt(keep(ks, stiff_modes));
  keep(cs, damped_modes);
  m.basis = orthonormal(columns);
  const Eigen::MatrixXd k = m.basis.transpose() * (ks * m.basis), c = m.basis.transpose() * (cs * m.basis);
  m.k = 0.5 * (k + k.transpose());  // exactly symmetric, as the operators are
  m.c = 0.5 * (c + c.transpose());
  return m;
}

ModeDescription describe_mode(const LinearisedMechanics& m, const Eigen::VectorXcd& reduced_shape, const Scene& scene) {
  ModeDescription d;
  if (reduced_shape.size() != m.basis.cols() || m.basis.cols() == 0) return d;
  const Eigen::VectorXcd scaled = m.basis.cast<std::complex<double>>() * reduced_shape;
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
  // Each spring's energy k |B u|^2 in physical displacements u (a mode no spring holds: its
  // dashpots' c |B u|^2).
  Eigen::VectorXcd u = scaled;
  for (Eigen::Index k = 0; k < u.size(); ++k) u[k] *= m.inv_sqrt_mass[k];
  auto energies = [&](bool springs) {
    double total[3] = {0, 0, 0}, best = -1;
    int best_kind = 0, best_contact = -1;
    std::vector<std::array<double, 3>> each(m.contacts.size());
    for (size_t p = 0; p < m.contacts.size(); ++p)
      for (int kind = 0; kind < 3; ++kind) {
        const SpringRow& r = m.rows[p][kind];
        std::complex<double> strain = 0;
        for (int a = 0; a < r.size; ++a) strain += r.by[a] * u[r.at[a]];
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
