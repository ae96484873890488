#include "common/parse_number.h"

#include <cmath>
#include <exception>

namespace ttz {
namespace {

// `parse(text, &used)` (std::stod, std::stoi) when it reads all of TEXT.
template <typename Parse>
auto Whole(const std::string& text, Parse parse) -> std::optional<decltype(parse(text, nullptr))> {
  size_t used = 0;
  try {
    const auto x = parse(text, &used);
    if (used == text.size()) return x;
  } catch (const std::exception&) {  // std::invalid_argument, std::out_of_range
  }
  return std::nullopt;
}

}  // namespace

std::optional<double> ParseDouble(const std::string& text) {
  const std::optional<double> x =
      Whole(text, [](const std::string& t, size_t* used) { return std::stod(t, used); });
  if (x && !std::isfinite(*x)) return std::nullopt;
  return x;
}

std::optional<int> ParseInt(const std::string& text) {
  return Whole(text, [](const std::string& t, size_t* used) { return std::stoi(t, used); });
}

}  // namespace ttz
