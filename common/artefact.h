// HDF5 artefacts (road.h5, lap.h5): atomic writing, schema checks, a unit on every dataset.
//
// Every file carries the root attributes `schema` (string, e.g. "ttz.road") and `schema_version`
// (integer). Every dataset carries the string attributes `units` (SI, "1" when dimensionless) and
// `description`. Dataset names may contain '/' (e.g. "left/lat"); groups are created as needed.
//
// Writing goes to "<path>.tmp.<pid>" in the same folder and is renamed onto `path` by Commit(), so
// a failed run never leaves a half-written artefact: the destructor removes an uncommitted file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ttz {

class ArtefactWriter {
 public:
  // Throws InputError (naming `path`) when the temporary file cannot be created, e.g. the folder
  // does not exist or is not writable.
  ArtefactWriter(const std::string& path, const std::string& schema, int schema_version);
  ~ArtefactWriter();
  ArtefactWriter(const ArtefactWriter&) = delete;
  ArtefactWriter& operator=(const ArtefactWriter&) = delete;

  void WriteVector(const std::string& name, const std::vector<double>& values,
                   const std::string& units, const std::string& description);
  void WriteIntVector(const std::string& name, const std::vector<int64_t>& values,
                      const std::string& units, const std::string& description);
  void WriteStringVector(const std::string& name, const std::vector<std::string>& values,
                         const std::string& description);

  // Root attributes.
  void WriteAttribute(const std::string& name, double value);
  void WriteAttribute(const std::string& name, int64_t value);
  void WriteAttribute(const std::string& name, const std::string& value);
  void WriteAttribute(const std::string& name, const char* value) { WriteAttribute(name, std::string(value)); }
  void WriteBoolAttribute(const std::string& name, bool value);  // stored as int8 0/1

  // Closes the file and renames it onto the final path. Nothing may be written afterwards.
  void Commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class ArtefactReader {
 public:
  // Throws InputError when the file is missing, is not HDF5, or its `schema` / `schema_version`
  // differ from the expected ones (the message says found and expected). Versions from
  // oldest_version to schema_version are accepted (oldest_version 0: schema_version alone).
  ArtefactReader(const std::string& path, const std::string& schema, int schema_version, int oldest_version = 0);
  ~ArtefactReader();
  ArtefactReader(const ArtefactReader&) = delete;
  ArtefactReader& operator=(const ArtefactReader&) = delete;

  const std::string& path() const;
  int schema_version() const;  // the file's
  bool HasDataset(const std::string& name) const;
  bool HasAttribute(const std::string& name) const;

  // Throws InputError naming the file and dataset when it is missing, is not a 1-D numeric array,
  // or its `units` attribute differs from `expected_units`.
  std::vector<double> ReadVector(const std::string& name, const std::string& expected_units) const;
  std::vector<int64_t> ReadIntVector(const std::string& name, const std::string& expected_units) const;
  // The same for a 1-D array of variable-length strings (ArtefactWriter::WriteStringVector), units "1".
  std::vector<std::string> ReadStringVector(const std::string& name) const;

  // Throw InputError naming the file and attribute when missing or of another type.
  double ReadDoubleAttribute(const std::string& name) const;
  int64_t ReadIntAttribute(const std::string& name) const;
  std::string ReadStringAttribute(const std::string& name) const;
  bool ReadBoolAttribute(const std::string& name) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// SHA-256 of a file's bytes as 64 lower-case hex digits (OpenSSL). Throws InputError if unreadable.
std::string FileSha256(const std::string& path);

// Throws InputError naming `path` when the folder it would be written to does not exist: the
// command-line tools check it before their work, so a typo in -o does not cost a fit or a solve.
void CheckOutputFolder(const std::string& path);

}  // namespace ttz
