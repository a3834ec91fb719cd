#include "src/scene/particle_file.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "src/base/error.h"
#include "src/scene/scene.h"
#include "src/base/nearest.h"
#include "src/base/atomic_write.h"
#include "src/base/text_format.h"

namespace kiln {

namespace {

// A file read line by line, each line numbered for messages.
class LineReader {
 public:
  // A file is read only if its size fits `limits`: a line holds one particle, in at most
  // max_line_bytes (a 1 GB sparse CSV was read for 49 s into 5.1 GB before its count was known).
  LineReader(const std::string& path, const ParticleFileLimits& limits) : path_(path) {
    // A device or a directory would be read forever or not at all.
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
      throw InputError({path, 0, ""}, "cannot read the particle file: no such file (or not a regular file)");
    const uintmax_t size = std::filesystem::file_size(path, error);
    const double most = (static_cast<double>(limits.max_particles) + header_lines) * max_line_bytes;
    if (!error && static_cast<double>(size) > most)
      throw InputError({path, 0, ""}, format("a file of %.4g bytes: more than %.4g, which the %lld particles this "
                                             "scene may hold take at %d bytes a line",
                                             static_cast<double>(size), most, limits.max_particles, max_line_bytes));
    in_.open(path, std::ios::binary);
    if (!in_) throw InputError({path, 0, ""}, "cannot open the particle file");
  }
  // The next line without its line end (CRLF files read as LF files) or the UTF-8 byte order mark
  // a spreadsheet writes before the first ("unknown column 'x'", listing x, was the message);
  // false at the end. A NUL byte is no text (it also cut the messages short).
  bool next(std::string& line) {
    // Byte by byte, so that a line is never read further than the longest a particle's takes.
    std::streambuf* in = in_.rdbuf();
    line.clear();
    int c = in->sbumpc();
    if (c == std::char_traits<char>::eof()) return false;
    ++number_;
    for (; c != std::char_traits<char>::eof() && c != '\n'; c = in->sbumpc()) {
      if (c == 0) fail(format("a NUL byte at column %zu: not a text file", line.size() + 1));
      if (line.size() >= static_cast<size_t>(max_line_bytes))
        fail(format("a line longer than %d bytes: a particle's line holds far fewer", max_line_bytes));
      line.push_back(static_cast<char>(c));
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number_ == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    return true;
  }
  static constexpr int max_line_bytes = 4096;
  static constexpr int header_lines = 1000;  // comments and a LAMMPS header
  int number() const { return number_; }
  [[noreturn]] void fail(const std::string& message) const { throw InputError({path_, number_, ""}, message); }
  [[noreturn]] void fail_at(int line, const std::string& message) const { throw InputError({path_, line, ""}, message); }

 private:
  std::string path_;
  std::ifstream in_;
  int number_ = 0;
};

std::string trimmed(const std::string& s) {
  const size_t first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// The whole text as a number, or nothing ("1.5x", "", "nan" and "inf" are not numbers here).
std::optional<double> real_of(const std::string& text) {
  const char* first = text.data();
  const char* last = first + text.size();
  if (first != last && *first == '+' && last - first > 1 && first[1] != '-' && first[1] != '+') ++first;
  double v = 0;
  const auto [end, error] = std::from_chars(first, last, v);
  if (error != std::errc() || end != last || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Whether a word is meant as a number (a header line or a section's line starts with one), which
// real_of then reads or refuses.
bool looks_numeric(const std::string& word) {
  const size_t first = word[0] == '+' || word[0] == '-' ? 1 : 0;
  return first < word.size() && (std::isdigit(static_cast<unsigned char>(word[first])) || word[first] == '.');
}

std::optional<long long> integer_of(const std::string& text) {
  long long v = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

void check_count(const LineReader& lines, long long count, const ParticleFileLimits& limits) {
  if (count > limits.max_particles)
    lines.fail(std::to_string(count) + " particles: more than the " + std::to_string(limits.max_particles) +
               " this scene can hold (see the memory limit of the scene's particles)");
}

// ---- LAMMPS data files ----

// One line of a LAMMPS data file: its words before any '#', and the comment after it.
struct DataLine {
  std::vector<std::string> words;
  std::string comment;
};
DataLine split_data_line(const std::string& line) {
  const size_t hash = line.find('#');
  return {words(line.substr(0, hash)), hash == std::string::npos ? "" : trimmed(line.substr(hash + 1))};
}

std::string joined(const std::vector<std::string>& w, size_t from) {
  std::string out;
  for (size_t k = from; k < w.size(); ++k) out += (out.empty() ? "" : " ") + w[k];
  return out;
}

class LammpsDataReader {
 public:
  LammpsDataReader(const std::string& path, const ParticleFileLimits& limits) : lines_(path, limits), limits_(limits) {}

  ParticleFile read() {
    std::string line;
    if (!lines_.next(line)) lines_.fail("an empty file: a LAMMPS data file starts with a title line");
    // Header lines start with numbers; the first line that does not is a section heading.
    DataLine d;
    bool more = next_nonblank(d);
    while (more && looks_numeric(d.words.front())) {
      header_line(d.words);
      more = next_nonblank(d);
    }
    while (more) {
      section(d);
      more = next_nonblank(d);
    }
    if (!seen_atoms_section_) lines_.fail("no Atoms section (a LAMMPS data file of atom_style sphere needs one)");
    return std::move(out_);
  }

 private:
  bool next_nonblank(DataLine& d) {
    for (std::string line; lines_.next(line);) {
      d = split_data_line(line);
      if (!d.words.empty()) return true;
    }
    return false;
  }

  void header_line(const std::vector<std::string>& w) {
    size_t numbers = 0;
    for (; numbers < w.size() && looks_numeric(w[numbers]); ++numbers)
      if (!real_of(w[numbers])) lines_.fail("'" + w[numbers] + "' is not a number");
    const std::string keyword = joined(w, numbers);
    if (!header_seen_.insert({keyword, lines_.number()}).second)
      lines_.fail("the header line '" + keyword + "' is given twice (also at line " +
                  std::to_string(header_seen_[keyword]) + ")");
    auto expect_numbers = [&](size_t n) {
      if (numbers != n)
        lines_.fail("the header line '" + keyword + "' takes " + std::to_string(n) + (n == 1 ? " number" : " numbers") +
                    ", got " + std::to_string(numbers));
    };
    auto count = [&](long long min_value) {
      expect_numbers(1);
      const auto n = integer_of(w[0]);
      if (!n || *n < min_value)
        lines_.fail("'" + w[0] + "' " + keyword + ": expected a whole number of at least " + std::to_string(min_value));
      return *n;
    };
    auto bounds = [&](double& lo, double& hi) {
      expect_numbers(2);
      lo = *real_of(w[0]);
      hi = *real_of(w[1]);
      if (!(hi > lo)) lines_.fail("'" + keyword + "': expected low < high, got " + w[0] + " " + w[1]);
    };
    double zlo = 0, zhi = 0;
    if (keyword == "atoms") {
      atoms_ = count(1);
      check_count(lines_, atoms_, limits_);
    } else if (keyword == "atom types") {
      types_ = count(1);
    } else if (keyword == "xlo xhi") {
      bounds(out_.xlo, out_.xhi);
    } else if (keyword == "ylo yhi") {
      bounds(out_.ylo, out_.yhi);
    } else if (keyword == "zlo zhi") {
      bounds(zlo, zhi);
    } else if (keyword == "xy xz yz") {
      lines_.fail("a tilted (triclinic) box: kiln reads orthogonal boxes only");
    } else {
      lines_.fail("the header line '" + (keyword.empty() ? joined(w, 0) : keyword) +
                  "' is not read by kiln: a data file of atom_style sphere has " +
                  "'N atoms', 'T atom types', 'xlo xhi', 'ylo yhi' and 'zlo zhi'");
    }
    out_.has_box = header_seen_.count("xlo xhi") && header_seen_.count("ylo yhi");
  }

  void section(const DataLine& heading) {
    // Sections are read by the header's count: a number here is a line too many.
    if (looks_numeric(heading.words.front()))
      lines_.fail("a line beyond the header's " + std::to_string(atoms_) + " atoms in the section above");
    const std::string name = joined(heading.words, 0);
    if (name != "Atoms" && name != "Velocities")
      lines_.fail("the section '" + name + "' is not read by kiln: it reads " + choices_nearest_first(name, {"Atoms", "Velocities"}) +
                  " (atom_style sphere)");
    if (atoms_ == 0) lines_.fail("the " + name + " section comes before the header's 'N atoms' line, or there is none");
    if (name == "Atoms") {
      if (seen_atoms_section_) lines_.fail("a second Atoms section");
      const std::string style = words(heading.comment).empty() ? "" : words(heading.comment).front();
      if (!style.empty() && style != "sphere")
        lines_.fail("an Atoms section of atom_style " + style +
                    ": kiln reads atom_style sphere (id type diameter density x y z)");
      seen_atoms_section_ = true;
      read_atoms();
    } else {
      if (!seen_atoms_section_) lines_.fail("the Velocities section comes before the Atoms section");
      if (out_.has_velocity) lines_.fail("a second Velocities section");
      read_velocities();
    }
  }

  // The k-th of the section's lines, or a message that the section ended early.
  DataLine section_line(const char* section, long long k) {
    DataLine d;
    if (!next_nonblank(d))
      lines_.fail("the " + std::string(section) + " section ends after " + std::to_string(k) + " of the header's " +
                  std::to_string(atoms_) + " atoms");
    if (!looks_numeric(d.words.front()))
      lines_.fail("the " + std::string(section) + " section ends after " + std::to_string(k) + " of the header's " +
                  std::to_string(atoms_) + " atoms, at '" + joined(d.words, 0) + "'");
    return d;
  }

  double number(const DataLine& d, size_t column, const char* name) const {
    const auto v = real_of(d.words[column]);
    if (!v) lines_.fail("column " + std::to_string(column + 1) + " (" + name + "): '" + d.words[column] + "' is not a number");
    return *v;
  }
  long long whole(const DataLine& d, size_t column, const char* name) const {
    const auto v = integer_of(d.words[column]);
    if (!v) lines_.fail("column " + std::to_string(column + 1) + " (" + name + "): '" + d.words[column] + "' is not a whole number");
    return *v;
  }

  void read_atoms() {
    out_.id.reserve(atoms_);
    for (long long k = 0; k < atoms_; ++k) {
      const DataLine d = section_line("Atoms", k);
      if (d.words.size() != 7 && d.words.size() != 10)
        lines_.fail("expected 7 values (id type diameter density x y z) or 10 (with image flags ix iy iz), got " +
                    std::to_string(d.words.size()));
      const long long id = whole(d, 0, "id");
      if (id < 1) lines_.fail("atom id " + d.words[0] + ": ids are whole numbers from 1");
      if (const auto [at, fresh] = line_of_id_.insert({id, lines_.number()}); !fresh)
        lines_.fail("atom id " + std::to_string(id) + " is given twice (also at line " + std::to_string(at->second) + ")");
      const long long type = whole(d, 1, "type");
      if (type < 1 || (types_ > 0 && type > types_))
        lines_.fail("atom type " + d.words[1] + ": the header declares types 1 to " + std::to_string(types_));
      const double diameter = number(d, 2, "diameter"), density = number(d, 3, "density");
      if (!(diameter >= 2 * shortest_length && diameter <= 2 * farthest_coordinate))
        lines_.fail("diameter " + d.words[2] + ": expected a radius in [1e-9, 1e6] m, as for a scene's radius");
      if (!(density > 0)) lines_.fail("density " + d.words[3] + ": expected a positive density");
      if (limits_.density > 0 && std::abs(density - limits_.density) > 1e-9 * limits_.density)
        lines_.fail("density " + d.words[3] + " differs from the material's " + message_number(limits_.density) +
                    " kg/m^3: kiln takes every mass from the material (mass_model); give the material's density");
      const double x = number(d, 4, "x"), y = number(d, 5, "y"), z = number(d, 6, "z");
      if (z != 0) lines_.fail("z = " + d.words[6] + ": kiln is 2D, a particle lies at z = 0");
      for (size_t c = 7; c < d.words.size(); ++c) whole(d, c, "image flag");
      out_.id.push_back(id);
      out_.position.push_back({x, y});
      out_.radius.push_back(diameter / 2);
      out_.density.push_back(density);
    }
    out_.velocity.assign(atoms_, Vec2{});
    out_.angular_velocity.assign(atoms_, 0.0);
  }

  void read_velocities() {
    std::map<long long, size_t> index;
    for (size_t i = 0; i < out_.id.size(); ++i) index[out_.id[i]] = i;
    std::map<long long, int> seen;
    for (long long k = 0; k < atoms_; ++k) {
      const DataLine d = section_line("Velocities", k);
      if (d.words.size() != 7) lines_.fail("expected 7 values (id vx vy vz wx wy wz), got " + std::to_string(d.words.size()));
      const long long id = whole(d, 0, "id");
      const auto i = index.find(id);
      if (i == index.end()) lines_.fail("atom id " + d.words[0] + " is not in the Atoms section");
      if (const auto [at, fresh] = seen.insert({id, lines_.number()}); !fresh)
        lines_.fail("atom id " + std::to_string(id) + " is given twice (also at line " + std::to_string(at->second) + ")");
      out_.velocity[i->second] = {number(d, 1, "vx"), number(d, 2, "vy")};
      number(d, 3, "vz");
      number(d, 4, "wx");
      number(d, 5, "wy");
      out_.angular_velocity[i->second] = number(d, 6, "wz");
    }
    out_.has_velocity = out_.has_angular_velocity = true;
  }

  LineReader lines_;
  ParticleFileLimits limits_;
  ParticleFile out_;
  long long atoms_ = 0, types_ = 0;
  bool seen_atoms_section_ = false;
  std::map<std::string, int> header_seen_;
  std::map<long long, int> line_of_id_;
};

// ---- CSV ----

std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    out.push_back(trimmed(line.substr(start, comma - start)));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

ParticleFile read_csv(const std::string& path, const ParticleFileLimits& limits) {
  LineReader lines(path, limits);
  const std::vector<std::string> known = {"id", "x", "y", "radius", "diameter", "vx", "vy", "omega", "temperature"};
  auto skipped = [](const std::string& line) {
    const std::string t = trimmed(line);
    return t.empty() || t.front() == '#';
  };
  std::string line;
  while (lines.next(line) && skipped(line)) {
  }
  if (lines.number() == 0 || skipped(line))
    lines.fail("no header row: a particle CSV starts with the names of its columns (x, y, radius, ...)");
  const std::vector<std::string> names = csv_fields(line);
  std::map<std::string, size_t> column;
  for (size_t c = 0; c < names.size(); ++c) {
    if (std::find(known.begin(), known.end(), names[c]) == known.end())
      lines.fail("unknown column '" + names[c] + "'; the columns are " + choices_nearest_first(names[c], known));
    if (!column.insert({names[c], c}).second) lines.fail("the column '" + names[c] + "' is given twice");
  }
  for (const char* required : {"x", "y"})
    if (!column.count(required)) lines.fail(std::string("no column '") + required + "' (x, y and radius or diameter are required)");
  if (column.count("radius") == column.count("diameter"))
    lines.fail("give one of the columns 'radius' or 'diameter'");
  const bool by_radius = column.count("radius");
  const int header_line = lines.number();

  ParticleFile out;
  out.has_velocity = column.count("vx") || column.count("vy");
  out.has_angular_velocity = column.count("omega");
  std::map<long long, int> line_of_id;
  while (lines.next(line)) {
    if (skipped(line)) continue;
    const std::vector<std::string> fields = csv_fields(line);
    if (fields.size() != names.size())
      lines.fail("expected " + std::to_string(names.size()) + " fields (as the header at line " +
                 std::to_string(header_line) + " names), got " + std::to_string(fields.size()));
    check_count(lines, out.size() + 1LL, limits);
    auto value = [&](const char* name, double fallback) {
      const auto c = column.find(name);
      if (c == column.end()) return fallback;
      const auto v = real_of(fields[c->second]);
      if (!v) lines.fail("column '" + std::string(name) + "': '" + fields[c->second] + "' is not a number");
      return *v;
    };
    long long id = out.size() + 1LL;
    if (const auto c = column.find("id"); c != column.end()) {
      const auto v = integer_of(fields[c->second]);
      if (!v) lines.fail("column 'id': '" + fields[c->second] + "' is not a whole number");
      id = *v;
    }
    if (const auto [at, fresh] = line_of_id.insert({id, lines.number()}); !fresh)
      lines.fail("id " + std::to_string(id) + " is given twice (also at line " + std::to_string(at->second) + ")");
    const double size = by_radius ? value("radius", 0) : value("diameter", 0);
    const double radius_of_size = by_radius ? size : 0.5 * size;
    if (!(radius_of_size >= shortest_length && radius_of_size <= farthest_coordinate))
      lines.fail(std::string(by_radius ? "radius " : "diameter ") + fields[column[by_radius ? "radius" : "diameter"]] +
                 ": expected a radius in [1e-9, 1e6] m, as for a scene's radius");
    out.id.push_back(id);
    out.position.push_back({value("x", 0), value("y", 0)});
    out.radius.push_back(by_radius ? size : size / 2);
    out.velocity.push_back({value("vx", 0), value("vy", 0)});
    out.angular_velocity.push_back(value("omega", 0));
    if (column.count("temperature")) {
      const double t = value("temperature", 0);
      if (const std::string why = temperature_refusal(t, fields[column["temperature"]]); !why.empty())
        lines.fail("temperature " + fields[column["temperature"]] + " C " + why);
      out.temperature.push_back(t);
    }
  }
  if (out.size() == 0) lines.fail("no particles: the file has a header row and no rows after it");
  return out;
}

}  // namespace

std::optional<ParticleFileFormat> particle_file_format_of(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".data" || ext == ".lmp") return ParticleFileFormat::lammps;
  if (ext == ".csv") return ParticleFileFormat::csv;
  return std::nullopt;
}

ParticleFile read_particle_file(const std::string& path, ParticleFileFormat format, const ParticleFileLimits& limits) {
  if (format == ParticleFileFormat::csv) return read_csv(path, limits);
  return LammpsDataReader(path, limits).read();
}

void write_lammps_data(const std::string& path, const ParticleFile& p, const std::string& title) {
  std::ostringstream s;
  s.precision(17);
  s << title << "\n\n" << p.size() << " atoms\n1 atom types\n\n"
    << p.xlo << ' ' << p.xhi << " xlo xhi\n" << p.ylo << ' ' << p.yhi << " ylo yhi\n-0.5 0.5 zlo zhi\n\nAtoms # sphere\n\n";
  for (int i = 0; i < p.size(); ++i)
    s << p.id[i] << " 1 " << 2 * p.radius[i] << ' ' << p.density[i] << ' ' << p.position[i].x << ' '
      << p.position[i].y << " 0 0 0 0\n";
  s << "\nVelocities\n\n";
  for (int i = 0; i < p.size(); ++i)
    s << p.id[i] << ' ' << p.velocity[i].x << ' ' << p.velocity[i].y << " 0 0 0 " << p.angular_velocity[i] << '\n';
  write_file_atomically(path, s.str());
}

}  // namespace kiln
