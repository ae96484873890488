#include "common/artefact.h"

#include <hdf5.h>
#include <openssl/evp.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/error.h"

namespace ttz {
namespace {

// An HDF5 identifier closed by the matching H5?close when it goes out of scope.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  hid_t release() {  // the caller closes it
    const hid_t id = id_;
    id_ = -1;
    return id;
  }

 private:
  hid_t id_;
  Closer close_;
};

void Check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what + " failed");
}

void SilenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

void WriteStringAttribute(hid_t object, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  Check(H5Tset_size(type.get(), H5T_VARIABLE), "string type");
  Check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "string type");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attribute(H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attribute.valid()) throw std::logic_error("attribute '" + name + "' written twice or not writable");
  const char* text = value.c_str();
  Check(H5Awrite(attribute.get(), type.get(), &text), "writing attribute " + name);
}

void WriteScalarAttribute(hid_t object, const std::string& name, hid_t type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attribute(H5Acreate2(object, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attribute.valid()) throw std::logic_error("attribute '" + name + "' written twice or not writable");
  Check(H5Awrite(attribute.get(), type, value), "writing attribute " + name);
}

std::string ReadStringAttributeOf(hid_t object, const std::string& name, const std::string& where) {
  Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attribute.valid()) throw InputError(where, "attribute '" + name + "' is missing");
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING) throw InputError(where, "attribute '" + name + "' is not a string");
  if (H5Tis_variable_str(type.get()) > 0) {
    Handle memtype(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memtype.get(), H5T_VARIABLE);
    H5Tset_cset(memtype.get(), H5Tget_cset(type.get()));
    char* text = nullptr;
    Check(H5Aread(attribute.get(), memtype.get(), &text), "reading attribute " + name);
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  const size_t size = H5Tget_size(type.get());
  std::string value(size, '\0');
  Handle memtype(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(memtype.get(), size);
  Check(H5Aread(attribute.get(), memtype.get(), value.data()), "reading attribute " + name);
  return value.substr(0, value.find('\0'));
}

}  // namespace

// ----------------------------------------------------------------------------------------- writer

struct ArtefactWriter::Impl {
  std::string path, temp_path;
  hid_t file = -1;
  bool committed = false;

  void Close() {
    if (file >= 0) H5Fclose(file);
    file = -1;
  }

  void WriteDataset(const std::string& name, hid_t file_type, hid_t mem_type, size_t count, const void* data,
                    const std::string& units, const std::string& description) {
    const hsize_t dims[1] = {count};
    Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
    Handle links(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
    H5Pset_create_intermediate_group(links.get(), 1);
    Handle create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    constexpr hsize_t kChunk = 4096;  // 60 k-sample channels compress well in 32 kB chunks
    if (count > kChunk && H5Tget_class(file_type) != H5T_STRING) {
      const hsize_t chunk[1] = {kChunk};
      H5Pset_chunk(create.get(), 1, chunk);
      H5Pset_shuffle(create.get());
      H5Pset_deflate(create.get(), 4);
    }
    Handle dataset(H5Dcreate2(file, name.c_str(), file_type, space.get(), links.get(), create.get(), H5P_DEFAULT),
                   H5Dclose);
    if (!dataset.valid()) throw std::logic_error("dataset '" + name + "' written twice or not writable");
    if (count > 0) Check(H5Dwrite(dataset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "writing " + name);
    WriteStringAttribute(dataset.get(), "units", units);
    WriteStringAttribute(dataset.get(), "description", description);
  }
};

ArtefactWriter::ArtefactWriter(const std::string& path, const std::string& schema, int schema_version)
    : impl_(new Impl) {
  SilenceHdf5();
  impl_->path = path;
  impl_->temp_path = path + ".tmp." + std::to_string(getpid());
  impl_->file = H5Fcreate(impl_->temp_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (impl_->file < 0) throw InputError(path, "cannot be written (does the folder exist and is it writable?)");
  WriteAttribute("schema", schema);
  WriteAttribute("schema_version", static_cast<int64_t>(schema_version));
}

ArtefactWriter::~ArtefactWriter() {
  if (impl_->committed) return;
  impl_->Close();
  std::remove(impl_->temp_path.c_str());
}

void ArtefactWriter::WriteVector(const std::string& name, const std::vector<double>& values, const std::string& units,
                                 const std::string& description) {
  impl_->WriteDataset(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values.size(), values.data(), units, description);
}

void ArtefactWriter::WriteIntVector(const std::string& name, const std::vector<int64_t>& values,
                                    const std::string& units, const std::string& description) {
  impl_->WriteDataset(name, H5T_STD_I64LE, H5T_NATIVE_INT64, values.size(), values.data(), units, description);
}

void ArtefactWriter::WriteStringVector(const std::string& name, const std::vector<std::string>& values,
                                       const std::string& description) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  std::vector<const char*> pointers;
  for (const auto& v : values) pointers.push_back(v.c_str());
  impl_->WriteDataset(name, type.get(), type.get(), values.size(), pointers.data(), "1", description);
}

void ArtefactWriter::WriteAttribute(const std::string& name, double value) {
  WriteScalarAttribute(impl_->file, name, H5T_NATIVE_DOUBLE, &value);
}
void ArtefactWriter::WriteAttribute(const std::string& name, int64_t value) {
  WriteScalarAttribute(impl_->file, name, H5T_NATIVE_INT64, &value);
}
void ArtefactWriter::WriteAttribute(const std::string& name, const std::string& value) {
  WriteStringAttribute(impl_->file, name, value);
}
void ArtefactWriter::WriteBoolAttribute(const std::string& name, bool value) {
  const int8_t v = value ? 1 : 0;
  WriteScalarAttribute(impl_->file, name, H5T_NATIVE_INT8, &v);
}

void ArtefactWriter::Commit() {
  Check(H5Fflush(impl_->file, H5F_SCOPE_GLOBAL), "flush");
  impl_->Close();
  if (std::rename(impl_->temp_path.c_str(), impl_->path.c_str()) != 0) {
    std::remove(impl_->temp_path.c_str());
    throw InputError(impl_->path, "cannot be written (rename of the temporary file failed)");
  }
  impl_->committed = true;
}

// ----------------------------------------------------------------------------------------- reader

struct ArtefactReader::Impl {
  std::string path;
  int64_t version = 0;  // the file's schema_version
  hid_t file = -1;
  ~Impl() {
    if (file >= 0) H5Fclose(file);
  }
  std::string Where(const std::string& name) const { return path + ": '" + name + "'"; }

  hid_t OpenAttribute(const std::string& name) const {
    const hid_t a = H5Aopen(file, name.c_str(), H5P_DEFAULT);
    if (a < 0) throw InputError(path, "attribute '" + name + "' is missing");
    return a;
  }

  // Opens dataset `name` (the caller closes it), checked to be a 1-D array of numbers (or of
  // variable-length strings) with units `expected_units`; its length in `n`.
  hid_t Open1D(const std::string& name, const std::string& expected_units, bool strings, hsize_t* n) const {
    if (!Exists(name)) throw InputError(path, "dataset '" + name + "' is missing");
    Handle dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
    Handle space(H5Dget_space(dataset.get()), H5Sclose);
    Handle type(H5Dget_type(dataset.get()), H5Tclose);
    const H5T_class_t cls = H5Tget_class(type.get());
    const bool of_kind = strings ? cls == H5T_STRING && H5Tis_variable_str(type.get()) > 0
                                 : cls == H5T_FLOAT || cls == H5T_INTEGER;
    if (H5Sget_simple_extent_ndims(space.get()) != 1 || !of_kind)
      throw InputError(path, "dataset '" + name + "' is not a 1-D " + (strings ? "variable-length string" : "numeric") +
                                 " array");
    const std::string units = ReadStringAttributeOf(dataset.get(), "units", Where(name));
    if (units != expected_units)
      throw InputError(path, "dataset '" + name + "' has units '" + units + "', '" + expected_units + "' expected");
    H5Sget_simple_extent_dims(space.get(), n, nullptr);
    return dataset.release();
  }

  template <typename T>
  std::vector<T> Read(const std::string& name, const std::string& expected_units, hid_t mem_type) const {
    hsize_t n = 0;
    Handle dataset(Open1D(name, expected_units, false, &n), H5Dclose);
    std::vector<T> values(n);
    if (n > 0) Check(H5Dread(dataset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), "reading " + name);
    return values;
  }

  std::vector<std::string> ReadStrings(const std::string& name) const {
    hsize_t n = 0;
    Handle dataset(Open1D(name, "1", true, &n), H5Dclose);
    Handle type(H5Dget_type(dataset.get()), H5Tclose);
    Handle memtype(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memtype.get(), H5T_VARIABLE);
    H5Tset_cset(memtype.get(), H5Tget_cset(type.get()));
    std::vector<char*> texts(n, nullptr);
    if (n > 0) Check(H5Dread(dataset.get(), memtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, texts.data()), "reading " + name);
    std::vector<std::string> values;
    for (char* text : texts) {
      values.emplace_back(text ? text : "");
      H5free_memory(text);
    }
    return values;
  }

  bool Exists(const std::string& name) const {
    size_t pos = 0;
    while (true) {
      pos = name.find('/', pos + 1);
      const std::string prefix = name.substr(0, pos);
      if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
      if (pos == std::string::npos) return true;
    }
  }
};

ArtefactReader::ArtefactReader(const std::string& path, const std::string& schema, int schema_version,
                               int oldest_version)
    : impl_(new Impl) {
  SilenceHdf5();
  impl_->path = path;
  if (!std::filesystem::exists(path)) throw InputError(path, "file not found");
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(path, "not an HDF5 file (a " + schema + " artefact expected)");
  impl_->file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (impl_->file < 0) throw InputError(path, "cannot be opened as HDF5");
  const std::string found = HasAttribute("schema") ? ReadStringAttribute("schema") : "(none)";
  if (found != schema) throw InputError(path, "schema '" + found + "' found, '" + schema + "' expected");
  impl_->version = ReadIntAttribute("schema_version");
  const int oldest = oldest_version > 0 ? oldest_version : schema_version;
  if (impl_->version < oldest || impl_->version > schema_version) {
    const std::string expected = oldest == schema_version
                                     ? std::to_string(schema_version)
                                     : std::to_string(oldest) + " to " + std::to_string(schema_version);
    throw InputError(path, "schema_version " + std::to_string(impl_->version) + " found, " + expected +
                               " expected (re-create the file with this version of the tools)");
  }
}

ArtefactReader::~ArtefactReader() = default;

const std::string& ArtefactReader::path() const { return impl_->path; }
int ArtefactReader::schema_version() const { return static_cast<int>(impl_->version); }
bool ArtefactReader::HasDataset(const std::string& name) const { return impl_->Exists(name); }
bool ArtefactReader::HasAttribute(const std::string& name) const {
  return H5Aexists(impl_->file, name.c_str()) > 0;
}

std::vector<double> ArtefactReader::ReadVector(const std::string& name, const std::string& expected_units) const {
  return impl_->Read<double>(name, expected_units, H5T_NATIVE_DOUBLE);
}
std::vector<int64_t> ArtefactReader::ReadIntVector(const std::string& name, const std::string& expected_units) const {
  return impl_->Read<int64_t>(name, expected_units, H5T_NATIVE_INT64);
}

std::vector<std::string> ArtefactReader::ReadStringVector(const std::string& name) const {
  return impl_->ReadStrings(name);
}

double ArtefactReader::ReadDoubleAttribute(const std::string& name) const {
  Handle attribute(impl_->OpenAttribute(name), H5Aclose);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER) throw InputError(impl_->path, "attribute '" + name + "' is not a number");
  double value = 0;
  Check(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value), "reading attribute " + name);
  return value;
}

int64_t ArtefactReader::ReadIntAttribute(const std::string& name) const {
  Handle attribute(impl_->OpenAttribute(name), H5Aclose);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_INTEGER)
    throw InputError(impl_->path, "attribute '" + name + "' is not an integer");
  int64_t value = 0;
  Check(H5Aread(attribute.get(), H5T_NATIVE_INT64, &value), "reading attribute " + name);
  return value;
}

std::string ArtefactReader::ReadStringAttribute(const std::string& name) const {
  return ReadStringAttributeOf(impl_->file, name, impl_->path);
}

bool ArtefactReader::ReadBoolAttribute(const std::string& name) const { return ReadIntAttribute(name) != 0; }

// ------------------------------------------------------------------------------------------ SHA-256

std::string FileSha256(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot be read");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr);
  std::vector<char> block(1 << 20);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    EVP_DigestUpdate(ctx.get(), block.data(), static_cast<size_t>(in.gcount()));
  }
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(ctx.get(), digest, &length);
  std::string hex;
  char byte[3];
  for (unsigned int i = 0; i < length; ++i) {
    std::snprintf(byte, sizeof byte, "%02x", digest[i]);
    hex += byte;
  }
  return hex;
}

void CheckOutputFolder(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::absolute(path).parent_path();
  if (!std::filesystem::is_directory(folder))
    throw InputError(path, "cannot be written (the folder " + folder.string() + " does not exist)");
}

}  // namespace ttz
