// Error types and process exit codes shared by every command-line tool.
//
// Libraries throw; only the `main`s catch, print one line on stderr and exit with the code below.
#pragma once

#include <stdexcept>
#include <string>

namespace ttz {

// Process exit codes of road_fit and lap.
enum ExitCode : int {
  kExitOk = 0,
  kExitOther = 1,         // an unexpected failure (I/O error, library error, bug)
  kExitBadInput = 2,      // a bad input file, option or value; nothing was written
  kExitNotConverged = 3,  // the solver did not converge; the artefact says so (converged = false)
  kExitNotResolved = 4,   // lap: the solver converged, but its answer failed the re-simulation
                          // check (the mesh does not resolve the dynamics to 0.1 %); the artefact
                          // says so (resim_passed = false)
};

// A defect of the user's input. `where` names the file and, when known, the line/row, column or
// key ("road.csv:12: column 'lat'"); `what` says what is wrong and what was expected.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what) {}
};

// Formats a location "file:row" (row 1-based as a text editor shows it) or "file" when row <= 0.
std::string Where(const std::string& file, long row = 0);

}  // namespace ttz
