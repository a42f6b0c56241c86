#include "optim/ceres_logging.h"

#include <glog/logging.h>

namespace slt {

void ShowOnlyCeresErrors() {
  // Set once: the static's initialisation is thread-safe, and a stricter level set by the
  // program is kept.
  static const bool once = [] {
    if (FLAGS_minloglevel < google::GLOG_ERROR) FLAGS_minloglevel = google::GLOG_ERROR;
    return true;
  }();
  (void)once;
}

}  // namespace slt
