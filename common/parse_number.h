// Whole-string number parsing for command-line values (`lap_bench` arguments, Ipopt options by
// name) and bike.yaml's integers: the text must be one finite number with nothing after it.
// (CSV cells have their own checks with file and line, common/csv.h, which also accept numbers
// that underflow to a denormal; std::stod, used here, reports those as out of range.)
#pragma once

#include <optional>
#include <string>

namespace ttz {

// TEXT as a double, all of it (leading blanks allowed, as std::stod does); nullopt when TEXT is
// empty, not a number, has characters after the number, is out of range (also when it underflows,
// e.g. "1e-310"), or is nan or inf.
std::optional<double> ParseDouble(const std::string& text);

// TEXT as an int, all of it, in decimal; nullopt as ParseDouble, also for "1.5" or "1e3".
std::optional<int> ParseInt(const std::string& text);

}  // namespace ttz
