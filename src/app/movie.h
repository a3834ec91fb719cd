// A movie of a run, drawn after it from DIR/result.h5 (kiln movie DIR; kiln run --movie FIELD
// calls it when the run ends or a signal stops it): one PNG per frame in DIR/movie/, by the
// picture's renderer (picture.cpp), and DIR/movie.mp4 (H.264, yuv420p) encoded by ffmpeg when it
// is there. Drawing after the run, from every frame, gives every frame the same colour scale (the
// robust range of all frames' values, colour_scale.h) and the same view (all frames' extent), so a
// colour and a place mean the same throughout; the run itself pays nothing for it.
//
// Nothing half-written lies under a final name: the frames are drawn into DIR/movie.tmp/, which
// then replaces DIR/movie/, and ffmpeg writes DIR/movie.mp4.tmp, renamed when it succeeds. A
// movie.mp4 of earlier frames is removed when new frames are published.
#pragma once
#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// The fields a movie colours the discs by: speed (m/s), temperature (C, thermal scenes) and
// species (the particle's material: a colour each, with a legend).
const std::vector<std::string>& movie_fields();

// InputError naming `option` when the scene cannot be drawn by `field` (temperature without heat).
void check_movie_field(const Scene& scene, const std::string& field, const std::string& option);

// The scene the run in `dir` ran, as its checkpoint.h5 records it (every run that ends or is
// stopped writes one beside result.h5): the materials and the particles of walls, which
// result.h5 does not hold.
Scene scene_of_run(const std::string& dir);

struct MovieOptions {
  std::string field = "speed";
  int fps = 25;
  std::string ffmpeg;  // the encoder's path; empty: frames only
  bool quiet = false;  // no progress line
};

struct Movie {
  int frames = 0;
  std::string frames_dir;  // DIR/movie
  std::string mp4;         // DIR/movie.mp4, or "" when it was not encoded
  std::string failure;     // why ffmpeg failed (the frames are kept), or ""
  int stopped_by = 0;      // a stop signal received while drawing: nothing was published
};

// Draws the movie of the run in `dir` (whose scene is `scene`). Throws InputError when result.h5
// is missing or unreadable or another scene's, OutputError when a frame cannot be written (its
// temporary directory is removed).
Movie write_movie(const std::string& dir, const Scene& scene, const MovieOptions& options);

}  // namespace kiln
