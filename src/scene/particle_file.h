// Particle files: an initial particle set read from a LAMMPS data file or a CSV table, so that kiln
// and other codes (the peers of bench/run.sh) start from the same particles.
//
// LAMMPS data file, atom_style sphere (the format of LAMMPS' read_data and write_data):
//   line 1        a title (skipped)
//   header        "N atoms" (required), "T atom types", "xlo xhi", "ylo yhi", "zlo zhi"
//   Atoms # sphere   one line per atom: id type diameter density x y z [ix iy iz]
//   Velocities       optional, one line per atom: id vx vy vz wx wy wz
// A section is a heading line, a blank line, then its lines; '#' starts a comment. Units are SI
// (LAMMPS `units si`). kiln is 2D: z must be 0, and of a velocity line it takes vx, vy and wz.
// Image flags are read and ignored: positions are taken as written (write_data writes them
// wrapped into the box). The type is checked against "atom types" and otherwise not used: a
// scene gives the whole file one material.
//
// CSV: a header row naming the columns, then one row per particle, fields separated by commas
// (numbers only, no quoting); blank lines and lines starting with '#' are skipped. Columns, in any
// order: x, y (m) and one of radius or diameter (m) are required; id (a whole number, unique;
// default the row's number from 1), vx, vy (m/s), omega (rad/s, counter-clockwise) and
// temperature (degrees Celsius) are optional.
//
// Every error is an InputError naming the file and line: a missing header line or section, a bad
// number, a wrong number of fields, an unknown or repeated column, heading or header line, a
// repeated or unknown id, a diameter or radius that is not positive, a density other than the
// expected one.
#pragma once
#include <climits>
#include <optional>
#include <string>
#include <vector>

#include "src/base/vec2.h"

namespace kiln {

enum class ParticleFileFormat { lammps, csv };

// A particle set as a file gives it, in the file's order.
struct ParticleFile {
  std::vector<long long> id;
  std::vector<Vec2> position;             // m
  std::vector<double> radius;             // m
  std::vector<double> density;            // kg/m^3, LAMMPS data files only (empty for CSV)
  std::vector<Vec2> velocity;             // m/s, zero unless has_velocity
  std::vector<double> angular_velocity;   // rad/s, zero unless has_angular_velocity
  std::vector<double> temperature;        // C, empty unless the file gives temperatures
  bool has_velocity = false;
  bool has_angular_velocity = false;
  // The box of a LAMMPS data file (its xlo xhi and ylo yhi lines), m.
  bool has_box = false;
  double xlo = 0, xhi = 0, ylo = 0, yhi = 0;
  int size() const { return static_cast<int>(radius.size()); }
};

// What a reader accepts beyond the format.
struct ParticleFileLimits {
  long long max_particles = INT_MAX;  // more is an error, raised before they are stored
  double density = 0;                 // > 0: every density of a LAMMPS data file must equal it (to 1e-9)
};

// The format an extension names: .data and .lmp a LAMMPS data file, .csv a CSV table; nothing
// for any other (the scene must then say which).
std::optional<ParticleFileFormat> particle_file_format_of(const std::string& path);

ParticleFile read_particle_file(const std::string& path, ParticleFileFormat format,
                                const ParticleFileLimits& limits = {});

// Writes `particles` (which need a box and a density each) as a LAMMPS data file of atom_style
// sphere with a Velocities section, every number in 17 significant digits: read_particle_file and
// LAMMPS' read_data read back exactly what was written. Type 1 for every atom, image flags 0.
// Written under a temporary name and renamed (OutputError naming the file on failure).
void write_lammps_data(const std::string& path, const ParticleFile& particles, const std::string& title);

}  // namespace kiln
