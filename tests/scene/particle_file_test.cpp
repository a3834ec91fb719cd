// Particle files: LAMMPS data files and CSV tables read back exactly, what kiln writes read back
// bit for bit, every error naming the file and line, and particle sets of scenes read from them.
#include <cfloat>

#include "src/scene/particle_file.h"
#include "src/scene/particle_fill.h"
#include "tests/support.h"

namespace {

namespace fs = std::filesystem;
using kiln::ParticleFile;
using kiln::ParticleFileFormat;

fs::path write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file;
}

// The message reading `text` as a file of that format gives, or "" when it reads.
std::string error_reading(const fs::path& file, const std::string& text, ParticleFileFormat format,
                          const kiln::ParticleFileLimits& limits = {}) {
  write(file, text);
  try {
    kiln::read_particle_file(file.string(), format, limits);
  } catch (const kiln::InputError& e) {
    return e.what();
  }
  return "";
}

// Two atoms as LAMMPS' write_data writes them (the comments LAMMPS writes included).
const std::string two_atoms = R"(LAMMPS data file via write_data, version 29 Sep 2021, timestep = 0

2 atoms
1 atom types

0 0.01 xlo xhi
0 0.02 ylo yhi
-0.5 0.5 zlo zhi

Atoms # sphere

7 1 0.002 2500 0.0025 0.0030000000000000001 0 0 0 0
3 1 0.0017 2500 0.005 0.003 0 1 0 0

Velocities

3 0.25 -0.5 0 0 0 12.5
7 0.1 0 0 0 0 -3
)";

}  // namespace

TEST_CASE("a LAMMPS data file of atom_style sphere reads back exactly, in the file's order", "[particle_file]") {
  const fs::path file = write(kiln::testing::fresh_dir("pf_lammps") / "two.data", two_atoms);
  REQUIRE(kiln::particle_file_format_of(file.string()) == ParticleFileFormat::lammps);
  const ParticleFile p = kiln::read_particle_file(file.string(), ParticleFileFormat::lammps);
  REQUIRE(p.size() == 2);
  CHECK(p.id == std::vector<long long>{7, 3});
  CHECK(p.radius == std::vector<double>{0.001, 0.0017 / 2});
  CHECK(p.density == std::vector<double>{2500, 2500});
  CHECK(p.position[0].x == 0.0025);
  CHECK(p.position[0].y == 0.0030000000000000001);
  CHECK(p.position[1].x == 0.005);  // image flags are read and not applied
  CHECK(p.has_velocity);
  CHECK(p.velocity[0].x == 0.1);  // matched by id, not by line
  CHECK(p.angular_velocity[0] == -3);
  CHECK(p.velocity[1].x == 0.25);
  CHECK(p.velocity[1].y == -0.5);
  CHECK(p.angular_velocity[1] == 12.5);
  CHECK(p.temperature.empty());
  REQUIRE(p.has_box);
  CHECK(p.xlo == 0);
  CHECK(p.xhi == 0.01);
  CHECK(p.yhi == 0.02);
  fs::remove_all(file.parent_path());
}

TEST_CASE("a particle CSV reads back exactly, its columns in any order", "[particle_file]") {
  const fs::path file = write(kiln::testing::fresh_dir("pf_csv") / "set.csv",
                              "# a comment line\n"
                              "temperature, y,x,diameter,id ,omega,vx,vy\r\n"
                              "20.5,0.01,0.02,0.002,4,1.5,0.125,-1e-3\r\n"
                              "\n"
                              "-10,0.03,+0.04,3e-3,9,0,0,0\r\n");
  REQUIRE(kiln::particle_file_format_of(file.string()) == ParticleFileFormat::csv);
  const ParticleFile p = kiln::read_particle_file(file.string(), ParticleFileFormat::csv);
  REQUIRE(p.size() == 2);
  CHECK(p.id == std::vector<long long>{4, 9});
  CHECK(p.position[0].x == 0.02);
  CHECK(p.position[0].y == 0.01);
  CHECK(p.position[1].x == 0.04);
  CHECK(p.radius == std::vector<double>{0.001, 0.0015});
  CHECK(p.velocity[0].x == 0.125);
  CHECK(p.velocity[0].y == -1e-3);
  CHECK(p.angular_velocity[0] == 1.5);
  CHECK(p.temperature == std::vector<double>{20.5, -10});
  CHECK(p.density.empty());
  CHECK_FALSE(p.has_box);

  // Without optional columns: ids count rows from 1, velocities are zero and not "given".
  write(file, "x,y,radius\n0,0,0.001\n1,1,0.002\n");
  const ParticleFile q = kiln::read_particle_file(file.string(), ParticleFileFormat::csv);
  CHECK(q.id == std::vector<long long>{1, 2});
  CHECK_FALSE(q.has_velocity);
  CHECK_FALSE(q.has_angular_velocity);
  fs::remove_all(file.parent_path());
}

TEST_CASE("what kiln writes as a LAMMPS data file reads back bit for bit", "[particle_file]") {
  kiln::Random rng(11);
  ParticleFile p;
  for (int i = 0; i < 500; ++i) {
    p.id.push_back(i + 1);
    p.position.push_back({rng.uniform(0, 0.05), rng.uniform(1e-9, 0.2)});
    p.radius.push_back(rng.uniform(0.0008, 0.0012));
    p.density.push_back(2500);
    p.velocity.push_back({rng.uniform(-1, 1) * 1e-7, rng.uniform(-1, 1) * DBL_MIN * 3});
    p.angular_velocity.push_back(rng.uniform(-100, 100));
  }
  p.has_velocity = p.has_angular_velocity = p.has_box = true;
  p.xhi = 0.1 / 3;
  p.yhi = 0.2;
  const fs::path dir = kiln::testing::fresh_dir("pf_write");
  fs::create_directories(dir);
  const std::string file = (dir / "pile.data").string();
  kiln::write_lammps_data(file, p, "a test pile");
  const ParticleFile q = kiln::read_particle_file(file, ParticleFileFormat::lammps, {INT_MAX, 2500});
  CHECK(q.id == p.id);
  CHECK(q.radius == p.radius);
  CHECK(q.density == p.density);
  CHECK(q.angular_velocity == p.angular_velocity);
  bool same = true;
  for (int i = 0; i < p.size(); ++i)
    same = same && q.position[i].x == p.position[i].x && q.position[i].y == p.position[i].y &&
           q.velocity[i].x == p.velocity[i].x && q.velocity[i].y == p.velocity[i].y;
  CHECK(same);
  CHECK(q.xlo == p.xlo);
  CHECK(q.xhi == p.xhi);
  CHECK(q.yhi == p.yhi);
  fs::remove_all(dir);
}

TEST_CASE("every error of a LAMMPS data file names the file, the line and what is wrong", "[particle_file]") {
  const fs::path file = kiln::testing::fresh_dir("pf_lammps_errors") / "pile.data";
  const std::string f = file.string();
  auto error = [&](const std::string& text, const kiln::ParticleFileLimits& limits = {}) {
    return error_reading(file, text, ParticleFileFormat::lammps, limits);
  };
  using kiln::testing::replaced;
  using Catch::Matchers::Contains;
  CHECK(error(two_atoms).empty());
  CHECK_THAT(error(replaced(two_atoms, "0.0030000000000000001", "0.0o3")), Contains(f + ":12: column 6 (y): '0.0o3' is not a number"));
  CHECK_THAT(error(replaced(two_atoms, "7 1 0.002 2500 0.0025 0.0030000000000000001 0 0 0 0", "7 1 0.002 2500 0.0025 0.003 0 0 0")),
             Contains(f + ":12: expected 7 values (id type diameter density x y z) or 10 (with image flags ix iy iz), got 9"));
  CHECK_THAT(error(replaced(two_atoms, "3 1 0.0017", "7 1 0.0017")), Contains(f + ":13: atom id 7 is given twice (also at line 12)"));
  CHECK_THAT(error(replaced(two_atoms, "3 1 0.0017", "3 1 -0.0017")), Contains(f + ":13: diameter -0.0017: expected a radius in [1e-9, 1e6] m"));
  CHECK_THAT(error(replaced(two_atoms, "3 1 0.0017", "3 1 0")), Contains(f + ":13: diameter 0: expected a radius in [1e-9, 1e6] m"));
  // A size a scene's radius: key would refuse is refused from a file too.
  CHECK_THAT(error(replaced(two_atoms, "3 1 0.0017", "3 1 1e-300")), Contains(f + ":13: diameter 1e-300: expected a radius in [1e-9, 1e6] m"));
  CHECK_THAT(error(replaced(two_atoms, "Atoms # sphere", "Atomz # sphere")),
             Contains(f + ":10: the section 'Atomz' is not read by kiln: it reads 'Atoms' or 'Velocities'"));
  CHECK_THAT(error(replaced(two_atoms, "Atoms # sphere", "Atoms # atomic")), Contains(f + ":10: an Atoms section of atom_style atomic"));
  CHECK_THAT(error(replaced(two_atoms, "3 0.25", "5 0.25")), Contains(f + ":17: atom id 5 is not in the Atoms section"));
  CHECK_THAT(error(replaced(two_atoms, "2 atoms", "3 atoms")), Contains(f + ":15: the Atoms section ends after 2 of the header's 3 atoms, at 'Velocities'"));
  CHECK_THAT(error(replaced(two_atoms, "2 atoms", "1 atoms")), Contains(f + ":13: a line beyond the header's 1 atoms"));
  CHECK_THAT(error(replaced(two_atoms, "2 atoms", "2e999 atoms")), Contains(f + ":3: '2e999' is not a number"));
  CHECK_THAT(error(replaced(two_atoms, "7 1 0.002", "7x 1 0.002")), Contains(f + ":12: column 1 (id): '7x' is not a whole number"));
  CHECK_THAT(error(replaced(two_atoms, "2 atoms\n", "")), Contains(f + ":9: the Atoms section comes before the header's 'N atoms' line"));
  CHECK_THAT(error(replaced(two_atoms, "1 atom types", "1 atom types\n2 bonds")), Contains(f + ":5: the header line 'bonds' is not read by kiln"));
  CHECK_THAT(error(replaced(two_atoms, "1 atom types", "1 atom types\n3 atoms")), Contains(f + ":5: the header line 'atoms' is given twice (also at line 3)"));
  CHECK_THAT(error(replaced(two_atoms, "0 0.01 xlo", "0.01 0 xlo")), Contains(f + ":6: 'xlo xhi': expected low < high"));
  CHECK_THAT(error(replaced(two_atoms, "3 1 0.0017", "3 2 0.0017")), Contains(f + ":13: atom type 2: the header declares types 1 to 1"));
  CHECK_THAT(error(replaced(two_atoms, "0.005 0.003 0 1", "0.005 0.003 0.001 1")), Contains(f + ":13: z = 0.001: kiln is 2D"));
  CHECK_THAT(error(two_atoms.substr(0, two_atoms.find("Atoms #"))), Contains(f + ":9: no Atoms section"));
  CHECK_THAT(error(""), Contains(f + ": an empty file"));
  CHECK_THAT(error(two_atoms, {1, 0}), Contains(f + ":3: 2 particles: more than the 1 this scene can hold"));
  CHECK_THAT(error(replaced(two_atoms, "3 1 0.0017 2500", "3 1 0.0017 2400"), {INT_MAX, 2500}),
             Contains(f + ":13: density 2400 differs from the material's 2500 kg/m^3"));
  CHECK_THAT(error(replaced(two_atoms, "7 0.1 0 0 0 0 -3", "7 0.1 0 0 0 -3")), Contains(f + ":18: expected 7 values (id vx vy vz wx wy wz), got 6"));
  CHECK_THAT(error(replaced(two_atoms, "3 0.25", "7 0.25")), Contains(f + ":18: atom id 7 is given twice (also at line 17)"));
  fs::remove_all(file.parent_path());
}

TEST_CASE("every error of a particle CSV names the file, the line and what is wrong", "[particle_file]") {
  const fs::path file = kiln::testing::fresh_dir("pf_csv_errors") / "set.csv";
  const std::string f = file.string();
  auto error = [&](const std::string& text) { return error_reading(file, text, ParticleFileFormat::csv); };
  using Catch::Matchers::Contains;
  const std::string ok = "x,y,radius\n0,0,0.001\n0.01,0,0.001\n";
  CHECK(error(ok).empty());
  CHECK_THAT(error("x,y,radius,colour\n"), Contains(f + ":1: unknown column 'colour'; the columns are"));
  CHECK_THAT(error("x,y,radius,x\n"), Contains(f + ":1: the column 'x' is given twice"));
  CHECK_THAT(error("x,radius\n"), Contains(f + ":1: no column 'y'"));
  CHECK_THAT(error("x,y,radius,diameter\n"), Contains(f + ":1: give one of the columns 'radius' or 'diameter'"));
  CHECK_THAT(error("# only a comment\n\n"), Contains(f + ":2: no header row"));
  CHECK_THAT(error("x,y,radius\n"), Contains(f + ":1: no particles"));
  CHECK_THAT(error(ok + "0.02,0\n"), Contains(f + ":4: expected 3 fields (as the header at line 1 names), got 2"));
  CHECK_THAT(error(ok + "0.02,0,1mm\n"), Contains(f + ":4: column 'radius': '1mm' is not a number"));
  CHECK_THAT(error(ok + "0.02,nan,0.001\n"), Contains(f + ":4: column 'y': 'nan' is not a number"));
  CHECK_THAT(error(ok + "0.02,0,0\n"), Contains(f + ":4: radius 0: expected a radius in [1e-9, 1e6] m"));
  CHECK_THAT(error("id,x,y,diameter\n1,0,0,0.002\n2,0,0,-1\n"), Contains(f + ":3: diameter -1: expected a radius in [1e-9, 1e6] m"));
  CHECK_THAT(error("id,x,y,diameter\n1,0,0,0.002\n1,0,0,0.002\n"), Contains(f + ":3: id 1 is given twice (also at line 2)"));
  CHECK_THAT(error("id,x,y,diameter\n1.5,0,0,0.002\n"), Contains(f + ":2: column 'id': '1.5' is not a whole number"));
  CHECK_THAT(error("x,y,radius,temperature\n0,0,0.001,-300\n"), Contains(f + ":2: temperature -300 C is below absolute zero"));
  // Issue 28: a spreadsheet's byte order mark before the header (it said "unknown column 'x'",
  // listing x); a NUL byte (the message stopped at it); a line or a file longer than any pile's.
  CHECK(error("\xEF\xBB\xBF" + ok).empty());
  CHECK_THAT(error(ok + std::string("0.02,0,0.0\0\0\n", 13)), Contains(f + ":4: a NUL byte at column 11: not a text file"));
  CHECK_THAT(error(ok + std::string(5000, '1') + "\n"), Contains(f + ":4: a line longer than 4096 bytes"));
  std::string big = "x,y,radius\n";  // 5 MB where at most 2 particles (and comments) may come
  while (big.size() < 5000000) big += "0.01,0.01,0.001\n";
  CHECK_THAT(error_reading(file, big, ParticleFileFormat::csv, {2, 0}), Contains(f + ": a file of 5e+06 bytes: more than"));
  fs::remove_all(file.parent_path());
}

// A scene's particle set from a file beside it: positions, radii, velocities and temperatures
// from the file, the material from the scene; keys the file overrides are refused.
TEST_CASE("a scene reads a particle set from a file beside it", "[particle_file]") {
  const fs::path dir = kiln::testing::fresh_dir("pf_scene");
  write(dir / "piles" / "set.csv", "x,y,radius,vx,temperature\n0.01,0.01,0.002,0.5,80\n0.02,0.01,0.002,0,20\n");
  write(dir / "piles" / "two.data", two_atoms);
  const std::string scene_file = (dir / "scene.yaml").string();
  const std::string scene = R"(name: from_file
materials:
  glass: {density: 2500, stiffness: 1.0e4, restitution: 0.5, specific_heat: 840, conductivity: 1}
particles:
  - {material: glass, file: piles/set.csv}
dt: 1.0e-6
t_end: 0.001
)";
  const kiln::Scene s = kiln::parse_scene(scene, scene_file);
  REQUIRE(s.n_particles() == 2);
  CHECK(s.position[0].x == 0.01);
  CHECK(s.radius[1] == 0.002);
  CHECK(s.velocity[0].x == 0.5);
  CHECK(s.thermal);
  CHECK(s.temperature == std::vector<double>{80, 20});
  REQUIRE(s.inputs.size() == 1);
  CHECK(s.inputs[0].rfind("piles/set.csv\t", 0) == 0);  // a restart refuses the file changed

  // A LAMMPS data file, its format given explicitly.
  const fs::path renamed = dir / "piles" / "two.txt";
  fs::copy_file(dir / "piles" / "two.data", renamed);
  const kiln::Scene d = kiln::parse_scene(
      kiln::testing::replaced(kiln::testing::replaced(scene, "piles/set.csv}", "piles/two.txt, format: lammps}"),
                              ", specific_heat: 840, conductivity: 1", ""),
      scene_file);
  REQUIRE(d.n_particles() == 2);
  CHECK(d.angular_velocity[1] == 12.5);
  CHECK_FALSE(d.thermal);

  using Catch::Matchers::Contains;
  auto error = [&](const std::string& from, const std::string& to) {
    try {
      kiln::parse_scene(kiln::testing::replaced(scene, from, to), scene_file);
    } catch (const kiln::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string at = scene_file + ":5: key 'particles.0";
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, temperature: 20}"),
             Contains(at + ".temperature': the particle file gives every particle's temperature: remove this key"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, velocity: [0, 1]}"),
             Contains(at + ".velocity': the particle file gives every particle's velocity"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, radius: 0.001}"),
             Contains(at + ".radius': the particle file gives every radius"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, formt: csv}"), Contains(at + ".formt': unknown key"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, file: x.csv}"), Contains("given twice"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, format: xml}"),
             Contains(at + ".format': unknown value 'xml'; valid choices are"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/two.txt}"),
             Contains(at + ".file': the extension does not say the file's format"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/none.csv}"),
             Contains(at + ".file': " + (dir / "piles" / "none.csv").string() + ": cannot read the particle file"));
  CHECK_THAT(error("file: piles/set.csv}", "radius: 0.001, at: [[0, 0.01]], format: csv}"),
             Contains(at + ".format': 'format' does not apply here"));
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, at: [[0, 0.01]]}"),
             Contains("give exactly one of 'at' (a list of positions), 'fill', 'lattice' or 'file'"));
  // Fixed particles do not move: a file's velocities for them are refused, not dropped.
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/set.csv, fixed: true}"),
             Contains(at + ".file': attached and fixed particles move with their wall, but the file gives some of them"));
  write(dir / "piles" / "still.csv", "x,y,radius,vx,temperature\n0.01,0.01,0.002,0,80\n0.02,0.01,0.002,0,20\n");
  CHECK(error("file: piles/set.csv}", "file: piles/still.csv, fixed: true}").empty());
  // An error inside the file names the scene's key and the file's line.
  write(dir / "piles" / "bad.csv", "x,y,radius\n0,0,-1\n");
  CHECK_THAT(error("file: piles/set.csv}", "file: piles/bad.csv}"),
             Contains(at + ".file': " + (dir / "piles" / "bad.csv").string() + ":2: radius -1: expected a radius in [1e-9, 1e6] m"));
  // The data file's densities are the material's.
  CHECK(error("density: 2500", "density: 2000").empty());  // a CSV carries none
  try {
    kiln::parse_scene(kiln::testing::replaced(kiln::testing::replaced(scene, "piles/set.csv", "piles/two.data"), "density: 2500",
                                              "density: 2000"),
                      scene_file);
    FAIL("a density other than the material's was accepted");
  } catch (const kiln::InputError& e) {
    CHECK_THAT(e.what(), Contains(at + ".file': " + (dir / "piles" / "two.data").string() +
                                  ":12: density 2500 differs from the material's 2000 kg/m^3"));
  }
  fs::remove_all(dir);
}
