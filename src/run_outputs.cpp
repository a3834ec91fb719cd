#include "src/run_outputs.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "src/error.h"
#include "src/outputs.h"

namespace kiln {

namespace fs = std::filesystem;

const std::vector<std::string>& RunOutputs::names() {
  static const std::vector<std::string> n = {"result.h5",    "result.h5.tmp",   "result.xdmf",    "result.xdmf.tmp",
                                             "summary.json", "summary.json.tmp", "picture.png",    "picture.png.tmp",
                                             "checkpoint.h5", "checkpoint.h5.tmp", "result.h5.killed"};
  return n;
}

std::string RunOutputs::path(const std::string& name) const { return (fs::path(dir_) / name).string(); }

namespace {

void make_directory(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw OutputError("cannot create the output directory " + dir + ": " + error.message());
}

// Moves what an earlier run wrote in `dir` into dir/previous/.
void move_aside(const std::string& dir) {
  const fs::path previous = fs::path(dir) / "previous";
  bool any = false;
  for (const std::string& name : RunOutputs::names()) any = any || fs::exists(fs::path(dir) / name);
  if (!any) return;
  std::error_code error;
  fs::create_directories(previous, error);
  for (const std::string& name : RunOutputs::names()) {
    fs::remove(previous / name, error);
    if (fs::exists(fs::path(dir) / name)) fs::rename(fs::path(dir) / name, previous / name, error);
    if (error) throw OutputError("cannot move " + (fs::path(dir) / name).string() + " into " + previous.string() + ": " +
                                 error.message());
  }
}

}  // namespace

// One run at a time per directory: two runs writing into one would publish a mix of both. The
// lock is the kernel's (flock), so it goes with the process however that ends.
void RunOutputs::lock_directory() {
  make_directory(dir_);
  lock_ = ::open(path(".kiln.lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock_ < 0) throw OutputError("cannot create " + path(".kiln.lock") + ": " + std::strerror(errno));
  if (::flock(lock_, LOCK_EX | LOCK_NB) != 0)
    throw InputError(dir_ + " is in use by another kiln run (it holds " + path(".kiln.lock") +
                     "): wait for it to end, or give another --out");
}

RunOutputs::RunOutputs(const std::string& dir, const DemSystem& sys, const std::string& run_id) : dir_(dir), sys_(sys) {
  lock_directory();
  move_aside(dir_);
  try {
    h5_ = std::make_unique<H5Frames>(path("result.h5.tmp"), sys.particles(), sys.thermal());
    const Scene& scene = sys.scene();
    h5_->attribute("scene", scene.name);
    h5_->attribute("integrator", scene.integrator);
    h5_->attribute("dt", scene.dt);
    h5_->attribute("kiln_version", KILN_VERSION);
    h5_->attribute("run_id", run_id);
    std::vector<double> r(sys.particles());
    for (int i = 0; i < sys.particles(); ++i) r[i] = sys.radius(i);
    h5_->write_constant(r);
  } catch (...) {
    if (h5_) h5_->abandon();
    h5_.reset();
    std::remove(path("result.h5.tmp").c_str());
    throw;
  }
}

RunOutputs::RunOutputs(const std::string& dir, const DemSystem& sys, const std::string& run_id, int frames,
                       const Snapshot& checkpoint)
    : dir_(dir), sys_(sys), resumed_from_(&checkpoint) {
  lock_directory();
  // The result holding this run's frames up to the checkpoint: the result.h5.tmp of a killed run
  // (a killed resumed run's holds more than result.h5), the frames of a killed run kept by an
  // earlier restart (result.h5.killed), or the published result.h5.
  std::string original;
  for (const char* name : {"result.h5.tmp", "result.h5.killed", "result.h5"})
    if (fs::exists(path(name)) && H5Frames::frames_of_run(path(name), run_id) >= frames) {
      original = name;
      break;
    }
  if (original.empty())
    throw InputError(dir_ + ": none of result.h5, result.h5.tmp (a killed run's) and result.h5.killed holds the " +
                     std::to_string(frames) + " frames of run '" + run_id +
                     "' that the checkpoint continues: a result of another run, or frames lost");
  std::error_code error;
  if (original == "result.h5.tmp") {  // kept under a name of its own while a copy is extended
    fs::rename(path("result.h5.tmp"), path("result.h5.killed"), error);
    if (error) throw OutputError("cannot rename " + path("result.h5.tmp") + ": " + error.message());
    original = "result.h5.killed";
  }
  fs::copy_file(path(original), path("result.h5.tmp"), fs::copy_options::overwrite_existing, error);
  try {
    if (error)
      throw OutputError("cannot copy " + path(original) + " to " + path("result.h5.tmp") + ": " + error.message());
    h5_ = std::make_unique<H5Frames>(path("result.h5.tmp"), sys.particles(), sys.thermal(), frames);
    times_ = h5_->times();
  } catch (...) {
    if (h5_) h5_->abandon();
    h5_.reset();
    std::remove(path("result.h5.tmp").c_str());
    throw;
  }
}

RunOutputs::~RunOutputs() {
  if (!done_ && h5_) clean_up();
  if (lock_ >= 0) ::close(lock_);  // the lock goes last, after every file is in place
}

void RunOutputs::clean_up() {
  h5_->abandon();
  for (const char* name : {"result.h5.tmp", "result.xdmf.tmp", "summary.json.tmp", "picture.png.tmp",
                           "checkpoint.h5.tmp"})
    std::remove(path(name).c_str());
  if (!checkpointed_) return;
  if (!resumed_from_) {
    std::remove(path("checkpoint.h5").c_str());  // only of use beside the frames it continues
    return;
  }
  try {
    resumed_from_->write(path("checkpoint.h5"));  // the one that matches the original's frames
  } catch (const std::exception&) {
    // A later checkpoint is left: a restart from it reports the frames it misses.
  }
}

void RunOutputs::frame(double t, const double* y) {
  times_.push_back(t);
  h5_->append(t, y + sys_.x_at(), y + sys_.y_at(), y + sys_.vx_at(), y + sys_.vy_at(),
              sys_.rotates() ? y + sys_.angle_at() : nullptr, sys_.rotates() ? y + sys_.omega_at() : nullptr,
              sys_.thermal() ? y + sys_.temperature_at() : nullptr);
}

void RunOutputs::checkpoint(const Snapshot& s) {
  s.write(path("checkpoint.h5"));
  checkpointed_ = true;
}

void RunOutputs::finish(double t, const double* y, const nlohmann::json& summary, const std::string& title) {
  h5_->close();
  PictureInput pic;
  for (int i = 0; i < sys_.particles(); ++i) {
    pic.centre.push_back({y[sys_.x_at() + i], y[sys_.y_at() + i]});
    pic.radius.push_back(sys_.radius(i));
    pic.value.push_back(sys_.thermal() ? y[sys_.temperature_at() + i]
                                       : std::hypot(y[sys_.vx_at() + i], y[sys_.vy_at() + i]));
  }
  pic.value_label = sys_.thermal() ? "temperature" : "speed (m/s)";
  sys_.wall_geometry(t, y, pic.wall_a, pic.wall_b);
  pic.title = title;
  // Everything is written before anything is published: a failure leaves no final name behind.
  write_picture(path("picture.png.tmp"), pic);
  write_file(path("result.xdmf.tmp"), xdmf_document("result.h5", sys_.particles(), times_, sys_.thermal()));
  // A byte that is not UTF-8 (which the scene reader refuses) must not lose the run here.
  write_file(path("summary.json.tmp"), summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  for (const char* name : {"result.h5", "result.xdmf", "picture.png", "summary.json"})
    publish(path(std::string(name) + ".tmp"), path(name));
  std::remove(path("result.h5.killed").c_str());  // a resumed killed run's frames, now in result.h5
  done_ = true;
}

}  // namespace kiln
