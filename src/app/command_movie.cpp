// `kiln movie`: a run's frames drawn into DIR/movie/ and, with ffmpeg, DIR/movie.mp4.
#include <csignal>
#include <cstdio>

#include "src/app/command.h"
#include "src/base/error.h"
#include "src/base/stop_signal.h"
#include "src/base/subprocess.h"
#include "src/base/text_format.h"

namespace kiln {

int make_movie(const std::string& dir, const Scene& scene, MovieOptions options) {
  options.ffmpeg = find_program("ffmpeg");
  Movie movie;
  try {
    movie = write_movie(dir, scene, options);
  } catch (const OutputError& e) {
    std::fprintf(stderr, "error: %s (no movie was published)\n", bounded(e.what()).c_str());
    return exit_output_failed;
  }
  if (movie.stopped_by != 0) {
    std::fprintf(stderr, "movie of %s: stopped by %s; no frames were published\n", dir.c_str(),
                 signal_name(movie.stopped_by));
    return movie.stopped_by == SIGINT ? exit_sigint : exit_sigterm;
  }
  if (!movie.failure.empty()) {
    std::fprintf(stderr, "error: %s could not encode %s/movie.mp4 (%s); the %d frames are in %s/\n",
                 options.ffmpeg.c_str(), dir.c_str(), movie.failure.c_str(), movie.frames, movie.frames_dir.c_str());
    return exit_output_failed;
  }
  if (options.quiet) return exit_success;
  if (movie.mp4.empty())
    std::printf("movie: %d frames in %s/; installing Debian's ffmpeg (apt-get install ffmpeg) also gives "
                "%s/movie.mp4\n",
                movie.frames, movie.frames_dir.c_str(), dir.c_str());
  else
    std::printf("movie: %s (%d frames at %d per second; the frames are in %s/)\n", movie.mp4.c_str(), movie.frames,
                options.fps, movie.frames_dir.c_str());
  return exit_success;
}

namespace {

class MovieCommand final : public Command {
 public:
  explicit MovieCommand(CLI::App& app)
      : Command(app.add_subcommand(
            "movie", "draw a run's frames (DIR/result.h5) into DIR/movie/ and, with ffmpeg, DIR/movie.mp4")) {
    cli_->add_option("dir", dir_, "the output directory of a run")->required()->check(CLI::ExistingDirectory);
    cli_->add_option("--field", options_.field, "colour the discs by speed, temperature or species (material)")
        ->check(CLI::IsMember(movie_fields()));
    cli_->add_option("--fps", options_.fps, "frames per second of movie.mp4 (default 25)")->check(CLI::Range(1, 240));
    cli_->add_flag("--quiet", options_.quiet, "no progress and no closing line");
  }
  int run() override { return make_movie(dir_, scene_of_run(dir_), options_); }

 private:
  std::string dir_;
  MovieOptions options_;
};

}  // namespace

std::unique_ptr<Command> add_movie_command(CLI::App& app) { return std::make_unique<MovieCommand>(app); }

}  // namespace kiln
