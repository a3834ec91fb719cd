#include "src/app/movie.h"
#include "src/output/run_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "src/base/error.h"
#include "src/output/outputs.h"
#include "src/base/progress.h"
#include "src/output/result_reader.h"
#include "src/run/simulation.h"
#include "src/base/stop_signal.h"
#include "src/base/subprocess.h"

namespace kiln {

namespace fs = std::filesystem;

const std::vector<std::string>& movie_fields() {
  static const std::vector<std::string> fields = {"speed", "temperature", "species"};
  return fields;
}

void check_movie_field(const Scene& scene, const std::string& field, const std::string& option) {
  const auto& fields = movie_fields();
  if (std::find(fields.begin(), fields.end(), field) == fields.end())
    throw InputError(option + " '" + field + "': the fields are speed, temperature and species");
  if (field == "temperature" && !scene.thermal)
    throw InputError(option + " temperature: scene '" + scene.name +
                     "' is not thermal (its particles carry no temperature); draw speed or species");
}

Scene scene_of_run(const std::string& dir) {
  const std::string path = (fs::path(dir) / "checkpoint.h5").string();
  if (!fs::exists(path))
    throw InputError(path + " is missing: it records the scene (materials, particles of walls) a movie draws; "
                            "every run that ends or is stopped writes it beside result.h5: give the directory of "
                            "a run");
  SceneRecord source;
  return scene_of_checkpoint(Snapshot::read(path), {}, source);
}

namespace {

// The pictures of the frames of result.h5, coloured by one field, before the colour scale and
// the view that all frames share are set.
class FramePictures {
 public:
  FramePictures(const std::string& result, const Scene& scene, const std::string& field)
      : reader_(result), scene_(scene), field_(field) {
    if (reader_.particles() != scene.n_particles())
      throw InputError(result + " holds " + std::to_string(reader_.particles()) + " particles, scene '" + scene.name +
                       "' " + std::to_string(scene.n_particles()) + ": the result of another run");
    // Species: a category per material that some particle outside the walls is made of.
    category_of_material_.assign(scene.n_materials(), -1);
    for (int i = 0; i < scene.n_particles(); ++i) {
      int& c = category_of_material_[scene.material[i]];
      if (c < 0 && !of_wall(i)) {
        c = static_cast<int>(categories_.size());
        categories_.push_back(scene.materials[scene.material[i]].name);
      }
    }
  }
  int frames() const { return reader_.frames(); }
  double time(int k) const { return reader_.times()[k]; }
  bool of_wall(int i) const { return !scene_.attached.empty() && scene_.attached[i] != Scene::free_particle; }

  PictureInput picture(int k) {
    reader_.read(k, frame_);
    PictureInput pic;
    pic.centre = frame_.position;
    pic.radius = reader_.radius();
    pic.wall_a = frame_.wall_a;
    pic.wall_b = frame_.wall_b;
    for (int i = 0; i < reader_.particles(); ++i) {
      pic.of_wall.push_back(of_wall(i));
      if (field_ == "speed") pic.value.push_back(std::hypot(frame_.velocity[i].x, frame_.velocity[i].y));
      if (field_ == "temperature") pic.value.push_back(frame_.temperature[i]);
      if (field_ == "species") pic.value.push_back(std::max(0, category_of_material_[scene_.material[i]]));
    }
    if (field_ == "species") pic.categories = categories_;
    pic.value_label = field_ == "speed" ? "speed (m/s)" : field_ == "temperature" ? "temperature (C)" : "material";
    return pic;
  }

 private:
  ResultReader reader_;
  const Scene& scene_;
  std::string field_;
  std::vector<int> category_of_material_;
  std::vector<std::string> categories_;
  ResultReader::Frame frame_;
};

// A frame's time with as many decimals as the frames' spacing needs, the same in every frame
// (a title whose width jumps makes the movie flicker).
std::string time_label(double t, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "t = %.*f s", decimals, t);
  return text;
}

int decimals_of(const FramePictures& frames) {
  if (frames.frames() < 2) return 3;
  const double spacing = (frames.time(frames.frames() - 1) - frames.time(0)) / (frames.frames() - 1);
  return spacing > 0 ? std::clamp(static_cast<int>(std::ceil(-std::log10(spacing) - 1e-9)), 0, 9) : 3;
}

std::string frame_name(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05d.png", k);  // the pattern ffmpeg reads: frame_%05d.png
  return name;
}

// The last few lines ffmpeg wrote (its reason comes before "Conversion failed!").
std::string last_lines(const std::string& text, size_t count) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.find_first_not_of(" \r\t") != std::string::npos) lines.push_back(line);
  std::string out;
  for (size_t k = lines.size() > count ? lines.size() - count : 0; k < lines.size(); ++k)
    out += (out.empty() ? "" : "; ") + lines[k];
  return out.empty() ? "no message" : out;
}

// DIR/movie.mp4 from the frames in DIR/movie, through DIR/movie.mp4.tmp. Returns why it failed, or "".
std::string encode(const fs::path& dir, const MovieOptions& options) {
  const std::string tmp = (dir / "movie.mp4.tmp").string();
  const ProgramResult r = run_program(
      {options.ffmpeg, "-nostdin", "-hide_banner", "-loglevel", "error", "-y", "-framerate",
       std::to_string(options.fps), "-i", (dir / "movie" / "frame_%05d.png").string(),
       // H.264 in yuv420p (what every player reads) needs an even width and height.
       "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2:color=white", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags",
       "+faststart", "-f", "mp4", tmp});
  if (r.status != 0) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    return r.status < 0 ? r.errors : "exit status " + std::to_string(r.status) + ": " + last_lines(r.errors, 3);
  }
  publish(tmp, (dir / "movie.mp4").string());
  return "";
}

}  // namespace

Movie write_movie(const std::string& dir_name, const Scene& scene, const MovieOptions& options) {
  check_movie_field(scene, options.field, "--field");
  const fs::path dir(dir_name), tmp = dir / "movie.tmp";
  const std::string result = (dir / "result.h5").string();
  RunOutputs::require_published(dir_name, "result.h5", "draw it");
  FramePictures frames(result, scene, options.field);
  if (frames.frames() == 0) throw InputError(result + " holds no frames");
  Movie movie;
  movie.frames = frames.frames();
  movie.frames_dir = (dir / "movie").string();

  // One view and one colour scale for every frame: all frames' extent and values.
  PictureBounds bounds;
  std::vector<double> values;
  for (int k = 0; k < frames.frames(); ++k) {
    const PictureInput pic = frames.picture(k);
    bounds.grow(picture_bounds(pic));
    for (size_t i = 0; i < pic.value.size(); ++i)
      if (!pic.of_wall[i]) values.push_back(pic.value[i]);
  }
  const PictureView view = picture_view(bounds);
  const ColourScale scale = colour_scale(values);
  const int decimals = decimals_of(frames);

  const int signal_before = stop_signal();  // a run stopped by a signal still gets its movie
  std::error_code ignored;
  fs::remove_all(tmp, ignored);  // a killed drawing's
  Progress progress("movie", options.quiet);
  try {
    fs::create_directories(tmp);
    for (int k = 0; k < frames.frames(); ++k) {
      if (stop_signal() != signal_before) {
        progress.finish();
        fs::remove_all(tmp, ignored);
        movie.stopped_by = stop_signal();
        return movie;
      }
      PictureInput pic = frames.picture(k);
      pic.view = view;
      if (options.field != "species") pic.scale = scale;
      pic.title = scene.name + "   " + time_label(frames.time(k), decimals);
      pic.subtitle = "frame " + std::to_string(k + 1) + " of " + std::to_string(frames.frames());
      write_picture((tmp / frame_name(k)).string(), pic);
      progress.update(frames.time(k), frames.time(frames.frames() - 1));
    }
    progress.finish();
    // The new frames replace the old, and an older movie.mp4 goes with them.
    fs::remove_all(dir / "movie");
    fs::remove(dir / "movie.mp4");
    fs::rename(tmp, dir / "movie");
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(tmp, ignored);
    throw OutputError(std::string("cannot write the frames of the movie: ") + e.what());
  } catch (...) {
    fs::remove_all(tmp, ignored);
    throw;
  }
  if (options.ffmpeg.empty()) return movie;
  movie.failure = encode(dir, options);
  if (movie.failure.empty()) movie.mp4 = (dir / "movie.mp4").string();
  return movie;
}

}  // namespace kiln
