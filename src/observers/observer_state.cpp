#include "src/observers/observer.h"

namespace kiln {

void ObserverState::field(const std::string& key, double& v) {
  if (out_) out_->put(prefix_ + key, v);
  else v = in_->real(prefix_ + key);
}

void ObserverState::field(const std::string& key, bool& v) {
  if (out_) out_->put_integer(prefix_ + key, v);
  else v = in_->integer(prefix_ + key) != 0;
}

void ObserverState::field(const std::string& key, int& v) {
  if (out_) out_->put_integer(prefix_ + key, v);
  else v = static_cast<int>(in_->integer(prefix_ + key));
}

void ObserverState::field(const std::string& key, std::vector<double>& v) {
  if (out_) out_->put(prefix_ + key, v);
  else v = in_->reals(prefix_ + key);
}

}  // namespace kiln
