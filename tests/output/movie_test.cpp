// Movies of runs (src/app/movie.h): a frame per frame of result.h5, one colour scale and one view for
// all of them, species by material, and the MP4 only when ffmpeg is there and succeeds.
#include <cairo.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "src/app/movie.h"
#include "src/output/outputs.h"
#include "src/output/result_reader.h"
#include "src/run/simulation.h"
#include "src/base/subprocess.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> frames_in(const fs::path& dir) {
  std::vector<fs::path> frames;
  if (fs::exists(dir))
    for (const auto& entry : fs::directory_iterator(dir)) frames.push_back(entry.path());
  std::sort(frames.begin(), frames.end());
  return frames;
}

// The view every frame of the run in `dir` is drawn in: the extent of all its frames.
PictureView movie_view(const fs::path& dir) {
  ResultReader result((dir / "result.h5").string());
  PictureBounds bounds;
  ResultReader::Frame f;
  for (int k = 0; k < result.frames(); ++k) {
    result.read(k, f);
    PictureInput pic;
    pic.centre = f.position;
    pic.radius = result.radius();
    pic.wall_a = f.wall_a;
    pic.wall_b = f.wall_b;
    bounds.grow(picture_bounds(pic));
  }
  return picture_view(bounds);
}

// The colour (0-255 each) of a frame at the pixel where the point `at` (m) is drawn.
std::array<int, 3> colour_at(const fs::path& png, const PictureView& view, Vec2 at) {
  cairo_surface_t* image = cairo_image_surface_create_from_png(png.c_str());
  REQUIRE(cairo_surface_status(image) == CAIRO_STATUS_SUCCESS);
  REQUIRE(cairo_image_surface_get_width(image) == view.width());
  const Vec2 p = view.pixel(at);
  const unsigned char* row =
      cairo_image_surface_get_data(image) + static_cast<int>(p.y) * cairo_image_surface_get_stride(image);
  const uint32_t pixel = *reinterpret_cast<const uint32_t*>(row + 4 * static_cast<int>(p.x));
  cairo_surface_destroy(image);
  return {static_cast<int>((pixel >> 16) & 0xff), static_cast<int>((pixel >> 8) & 0xff),
          static_cast<int>(pixel & 0xff)};
}

Vec2 position_at(const fs::path& dir, int frame, int particle) {
  ResultReader result((dir / "result.h5").string());
  ResultReader::Frame f;
  result.read(frame, f);
  return f.position[particle];
}

// kiln with arguments (and an environment before it); its exit status and what it printed.
struct Command {
  int status = -1;
  std::string output;
};
Command run_kiln(const std::string& arguments, const fs::path& log, const std::string& environment = "") {
  const std::string cmd =
      environment + " " + KILN_BINARY + " " + arguments + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

// A disc at rest, one at 0.5 m/s that meets nothing, and one at 1 m/s that a soft wall slows to
// about 0.25 m/s at t = 0.008 s: no gravity, so the middle one keeps exactly 0.5 m/s.
const std::string three_speeds = R"(name: three_speeds
gravity: [0, 0]
materials:
  copper: {density: 8900, stiffness: 6000, restitution: 0.8}
  soft: {density: 8900, stiffness: 6000, restitution: 0.25}
particles:
  - material: copper
    radius: 0.002
    at: [[0.0, 0.0]]
    velocity: [0.5, 0]
  - material: copper
    radius: 0.002
    at: [[-0.05, 0.0]]
  - material: soft
    radius: 0.002
    at: [[0.0, 0.05]]
    velocity: [1.0, 0]
walls:
  - {name: stop, material: soft, segment: [[0.01, 0.03], [0.01, 0.07]]}
dt: 1.0e-6
t_end: 0.02
output_interval: 0.005
)";

// A copper disc, a glass disc and a copper disc attached to the floor.
const std::string two_species = R"(name: two_species
materials:
  copper: {density: 8900, stiffness: 6000, restitution: 0.8}
  glass: {density: 2500, stiffness: 6000, restitution: 0.8}
particles:
  - material: copper
    radius: 0.002
    at: [[0.0, 0.01]]
  - material: glass
    radius: 0.002
    at: [[0.01, 0.01]]
  - material: copper
    radius: 0.002
    at: [[-0.01, 0.002]]
    attach: floor
walls:
  - {name: floor, material: copper, segment: [[-0.05, 0], [0.05, 0]]}
dt: 1.0e-6
t_end: 0.002
output_interval: 0.001
)";

}  // namespace

TEST_CASE("a movie has one frame per frame of result.h5, and no MP4 without ffmpeg", "[movie]") {
  const fs::path dir = testing::fresh_dir("movie_frames");
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"), {"t_end=0.01"});
  run_scene(scene, {dir.string(), true});
  MovieOptions options;
  options.quiet = true;
  const Movie movie = write_movie(dir.string(), scene, options);
  const size_t frames = testing::read_dataset(dir / "result.h5", "time").size();
  REQUIRE(frames == 11);
  CHECK(movie.frames == 11);
  const auto files = frames_in(dir / "movie");
  REQUIRE(files.size() == frames);
  CHECK(files.front().filename() == "frame_00000.png");
  CHECK(files.back().filename() == "frame_00010.png");
  CHECK(movie.mp4.empty());
  CHECK_FALSE(fs::exists(dir / "movie.mp4"));
  CHECK_FALSE(fs::exists(dir / "movie.tmp"));
  fs::remove_all(dir);
}

// Per-frame scales would draw the 0.5 m/s disc mid-scale at first (0 to 1 m/s) and at the top at
// the end (0 to 0.25 m/s after the fast one is slowed).
TEST_CASE("a movie's colour scale is the whole run's: a disc at the same speed has the same colour in every frame",
          "[movie]") {
  const fs::path dir = testing::fresh_dir("movie_scale");
  const Scene scene = parse_scene(three_speeds, "three_speeds.yaml");
  run_scene(scene, {dir.string(), true});
  MovieOptions options;
  options.quiet = true;
  write_movie(dir.string(), scene, options);
  const auto files = frames_in(dir / "movie");
  REQUIRE(files.size() == 5);
  const PictureView view = movie_view(dir);
  const auto steady_first = colour_at(files.front(), view, position_at(dir, 0, 0));
  const auto steady_last = colour_at(files.back(), view, position_at(dir, 4, 0));
  CHECK(steady_first == steady_last);
  CHECK(steady_first != std::array<int, 3>{255, 255, 255});  // a disc, not the background
  // The slowed disc does change colour: the scale is not one colour for everything.
  CHECK(colour_at(files.front(), view, position_at(dir, 0, 2)) !=
        colour_at(files.back(), view, position_at(dir, 4, 2)));
  // And every frame has the same size (an MP4 needs it), though the discs move.
  for (const fs::path& f : files) {
    cairo_surface_t* image = cairo_image_surface_create_from_png(f.c_str());
    CHECK(cairo_image_surface_get_height(image) == view.height());
    cairo_surface_destroy(image);
  }
  fs::remove_all(dir);
}

TEST_CASE("a movie of species gives two materials two colours and a particle of a wall grey", "[movie]") {
  const fs::path dir = testing::fresh_dir("movie_species");
  const Scene scene = parse_scene(two_species, "two_species.yaml");
  run_scene(scene, {dir.string(), true});
  MovieOptions options;
  options.field = "species";
  options.quiet = true;
  write_movie(dir.string(), scene, options);
  const fs::path first = dir / "movie" / "frame_00000.png";
  const PictureView view = movie_view(dir);
  const auto copper = colour_at(first, view, position_at(dir, 0, 0));
  const auto glass = colour_at(first, view, position_at(dir, 0, 1));
  const auto attached = colour_at(first, view, position_at(dir, 0, 2));
  const std::array<int, 3> white = {255, 255, 255}, grey = {153, 153, 153};
  CHECK(copper != glass);
  for (const auto& c : {copper, glass}) {
    CHECK(c != white);
    CHECK(c != grey);
  }
  CHECK(attached == grey);
  fs::remove_all(dir);
}

TEST_CASE("a movie by temperature of a scene without heat is refused, naming the other fields", "[movie]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"));
  try {
    check_movie_field(scene, "temperature", "--movie");
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("--movie temperature") && Catch::Contains("not thermal") &&
                             Catch::Contains("speed or species"));
  }
  const fs::path dir = testing::fresh_dir("movie_bad_field");
  fs::create_directories(dir);
  const Command bad = run_kiln("movie " + dir.string() + " --field colour", dir / "log");
  CHECK(bad.status == 2);
  CHECK_THAT(bad.output, Catch::Contains("speed,temperature,species"));
  fs::remove_all(dir);
}

TEST_CASE("kiln run --movie without ffmpeg exits 0 with its frames and says where they are", "[movie]") {
  const fs::path dir = testing::fresh_dir("movie_no_ffmpeg");
  fs::create_directories(dir);
  const Command run = run_kiln("run " + testing::case_path("t1_free_fall.yaml") + " --t-end 0.005 --out " +
                               (dir / "out").string() + " --movie speed",
                           dir / "log", "PATH=/nonexistent");
  CHECK(run.status == 0);
  CHECK(frames_in(dir / "out" / "movie").size() == testing::read_dataset(dir / "out" / "result.h5", "time").size());
  CHECK_FALSE(fs::exists(dir / "out" / "movie.mp4"));
  CHECK_THAT(run.output, Catch::Contains((dir / "out" / "movie").string() + "/") &&
                             Catch::Contains("installing Debian's ffmpeg"));
  fs::remove_all(dir);
}

TEST_CASE("a failing ffmpeg leaves the frames, its reason and no movie.mp4", "[movie]") {
  const fs::path dir = testing::fresh_dir("movie_bad_ffmpeg");
  const fs::path bin = dir / "bin", out = dir / "out";
  fs::create_directories(bin);
  {
    // Writes part of its output file (its last argument), then fails as ffmpeg does.
    std::ofstream fake(bin / "ffmpeg");
    fake << "#!/bin/sh\nfor a; do out=$a; done\necho partial > \"$out\"\n"
            "echo \"Unknown encoder 'libx264'\" >&2\necho 'Conversion failed!' >&2\nexit 1\n";
  }
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  REQUIRE(run_kiln("run " + testing::case_path("t1_free_fall.yaml") + " --t-end 0.003 --quiet --out " + out.string(),
               dir / "run.log")
              .status == 0);
  // kiln movie reads the scene from the run's checkpoint.h5.
  const Command movie = run_kiln("movie " + out.string(), dir / "movie.log", "PATH=" + bin.string());
  CHECK(movie.status == 4);
  CHECK_THAT(movie.output, Catch::Contains("Unknown encoder 'libx264'") && Catch::Contains("frames are in"));
  CHECK(frames_in(out / "movie").size() == 4);
  CHECK_FALSE(fs::exists(out / "movie.mp4"));
  CHECK_FALSE(fs::exists(out / "movie.mp4.tmp"));
  fs::remove_all(dir);
}

TEST_CASE("with ffmpeg, movie.mp4 is H.264 in yuv420p with a picture per frame", "[movie]") {
  MovieOptions options;
  options.ffmpeg = find_program("ffmpeg");
  const std::string ffprobe = find_program("ffprobe");
  if (options.ffmpeg.empty() || ffprobe.empty()) {
    WARN("ffmpeg is not installed (apt-get install ffmpeg): the MP4 is not tested");
    return;
  }
  const fs::path dir = testing::fresh_dir("movie_mp4");
  const Scene scene = parse_scene(three_speeds, "three_speeds.yaml");
  run_scene(scene, {dir.string(), true});
  options.quiet = true;
  const Movie movie = write_movie(dir.string(), scene, options);
  CHECK(movie.failure.empty());
  REQUIRE(movie.mp4 == (dir / "movie.mp4").string());
  const std::string cmd = ffprobe + " -v error -count_frames -show_entries stream=codec_name,pix_fmt,nb_read_frames " +
                          "-of compact " + movie.mp4 + " > " + (dir / "probe").string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(dir / "probe");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  CHECK_THAT(text, Catch::Contains("codec_name=h264") && Catch::Contains("pix_fmt=yuv420p") &&
                       Catch::Contains("nb_read_frames=5"));
  CHECK_FALSE(fs::exists(dir / "movie.mp4.tmp"));
  fs::remove_all(dir);
}

TEST_CASE("kiln movie on a run that is still writing says so, not that it was killed", "[movie]") {
  // Issue 28: a missing result.h5 beside result.h5.tmp was always "killed"; a run holds
  // DIR/.kiln.lock while it writes.
  const fs::path dir = testing::fresh_dir("movie_running");
  fs::create_directories(dir);
  std::ofstream(dir / "result.h5.tmp") << "frames so far";
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"));
  MovieOptions options;
  options.quiet = true;
  CHECK_THROWS_WITH(write_movie(dir.string(), scene, options), Catch::Contains("it was killed"));
  const int lock = ::open((dir / ".kiln.lock").c_str(), O_CREAT | O_RDWR, 0644);
  REQUIRE(::flock(lock, LOCK_EX | LOCK_NB) == 0);  // as a run holds it
  CHECK_THROWS_WITH(write_movie(dir.string(), scene, options), Catch::Contains("is still running"));
  ::close(lock);
  fs::remove_all(dir);
}
