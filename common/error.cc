#include "common/error.h"

namespace ttz {

std::string Where(const std::string& file, long row) {
  return row > 0 ? file + ":" + std::to_string(row) : file;
}

}  // namespace ttz
