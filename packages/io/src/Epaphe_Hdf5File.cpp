#include "Epaphe_Hdf5File.hpp"

#include "Epaphe_Error.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
#include <system_error>
#include <utility>

static_assert(sizeof(hsize_t) == sizeof(std::uint64_t), "hsize_t must be 64-bit");

namespace epaphe::io {

namespace {

namespace fs = std::filesystem;

// ---- HDF5 error stack ------------------------------------------------------------------------

void silenceHdf5() {
  // Per thread in thread-safe builds, so done at every file opening rather than once.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

herr_t collectError(unsigned n, const H5E_error2_t* e, void* data) {
  auto* out = static_cast<std::vector<std::string>*>(data);
  if (n < 4 && e != nullptr) {
    std::string entry = e->func_name != nullptr ? e->func_name : "";
    if (e->desc != nullptr && e->desc[0] != '\0') entry += (entry.empty() ? "" : ": ") + std::string(e->desc);
    out->push_back(entry);
  }
  return 0;
}

/// The current HDF5 error stack, most specific entry first, as one line; clears it.
std::string hdf5ErrorText() {
  std::vector<std::string> entries;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collectError, &entries);
  H5Eclear2(H5E_DEFAULT);
  std::string text;
  for (const auto& e : entries) text += (text.empty() ? "" : "; ") + e;
  std::replace(text.begin(), text.end(), '\n', ' ');  // HDF5 embeds ctime() output
  return text;
}

/// Throws "<file>: <message>", with HDF5's description of the last failed call appended.
[[noreturn]] void fail(const std::string& file, const std::string& message, bool fromHdf5 = true) {
  ErrorBuilder eb;
  eb << file << ": " << message;
  if (fromHdf5) {
    const std::string detail = hdf5ErrorText();
    if (!detail.empty()) eb << " [HDF5: " << detail << "]";
  }
  eb.raise();
}

std::string sq(const std::string& s) {
  return "'" + s + "'";
}

std::string dimsText(const std::vector<hsize_t>& dims) {
  std::ostringstream os;
  os << '{';
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i) os << ',';
    if (dims[i] == H5S_UNLIMITED)
      os << "unlimited";
    else
      os << dims[i];
  }
  os << '}';
  return os.str();
}

// ---- RAII for HDF5 identifiers ---------------------------------------------------------------

class Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), closer_(o.closer_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      closer_ = o.closer_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset() {
    if (id_ >= 0 && closer_ != nullptr) closer_(id_);
    id_ = H5I_INVALID_HID;
  }

private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

// ---- object paths ----------------------------------------------------------------------------

std::vector<std::string> components(const std::string& file, const std::string& path) {
  if (path.empty()) fail(file, "empty object path; use '/' for the root group or '/group/name' for an object", false);
  std::vector<std::string> parts;
  std::string part;
  for (std::size_t i = 0; i <= path.size(); ++i) {
    if (i == path.size() || path[i] == '/') {
      if (part == "." || part == "..")
        fail(file, "object path " + sq(path) + " contains '" + part + "'; use absolute paths such as '/contact/gap'",
             false);
      if (!part.empty()) parts.push_back(part);
      part.clear();
    } else {
      part += path[i];
    }
  }
  return parts;
}

std::string joinPath(const std::vector<std::string>& parts, std::size_t count) {
  if (count == 0) return "/";
  std::string p;
  for (std::size_t i = 0; i < count; ++i) p += "/" + parts[i];
  return p;
}

std::string normalize(const std::string& file, const std::string& path) {
  const auto parts = components(file, path);
  return joinPath(parts, parts.size());
}

std::uint64_t elementCount(const std::string& file, const std::string& obj, const std::vector<hsize_t>& dims) {
  std::uint64_t n = 1;
  for (hsize_t d : dims) {
    if (d != 0 && n > std::numeric_limits<std::uint64_t>::max() / d)
      fail(file, "shape " + dimsText(dims) + " of " + sq(obj) + " overflows 64-bit sizes", false);
    n *= d;
  }
  return n;
}

}  // namespace

// ---- state -----------------------------------------------------------------------------------

namespace detail {

struct FileState {
  std::string path;
  Hdf5File::Mode mode = Hdf5File::Mode::ReadOnly;
  hid_t fid = H5I_INVALID_HID;
  std::vector<SeriesState*> series;  // live Series writing into this file
  bool compressSeries = true;
};

struct SeriesState {
  FileState* file = nullptr;  // null once the file was closed
  std::string filePath;       // kept for messages after the file closed
  std::string path;
  std::vector<std::uint64_t> recordDims;
  std::vector<hsize_t> fileRecordDims;
  std::size_t recordSize = 1;
  std::size_t bufferRecords = 1;
  std::vector<double> buffer;
  std::size_t buffered = 0;  // records in buffer
  hsize_t written = 0;       // records in the dataset
  Handle dset;
};

}  // namespace detail

using detail::FileState;
using detail::SeriesState;

namespace {

enum class Kind { None, Group, Dataset, Other };

const char* kindName(Kind k) {
  switch (k) {
    case Kind::None:
      return "nothing";
    case Kind::Group:
      return "a group";
    case Kind::Dataset:
      return "a dataset";
    case Kind::Other:
      return "a named datatype";
  }
  return "?";
}

Kind kindOfExisting(const FileState& f, const std::string& path) {
  Handle obj(H5Oopen(f.fid, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) fail(f.path, "cannot open object " + sq(path));
  switch (H5Iget_type(obj.get())) {
    case H5I_GROUP:
      return Kind::Group;
    case H5I_DATASET:
      return Kind::Dataset;
    default:
      return Kind::Other;
  }
}

/// What is at `path` (normalized); None if it or a parent is missing, or a parent is no group.
Kind kindOf(const FileState& f, const std::string& path) {
  if (path == "/") return Kind::Group;
  const auto parts = components(f.path, path);
  for (std::size_t i = 1; i <= parts.size(); ++i) {
    const std::string prefix = joinPath(parts, i);
    const htri_t link = H5Lexists(f.fid, prefix.c_str(), H5P_DEFAULT);
    if (link < 0) fail(f.path, "cannot look up " + sq(prefix));
    if (link == 0) return Kind::None;
    const htri_t target = H5Oexists_by_name(f.fid, prefix.c_str(), H5P_DEFAULT);
    if (target < 0) fail(f.path, "cannot look up " + sq(prefix));
    if (target == 0) return Kind::None;  // dangling soft or external link
    const Kind k = kindOfExisting(f, prefix);
    if (i == parts.size()) return k;
    if (k != Kind::Group) return Kind::None;
  }
  return Kind::None;
}

/// Creates the missing parent groups of `path` (normalized).
void ensureParents(const FileState& f, const std::string& path) {
  const auto parts = components(f.path, path);
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const std::string prefix = joinPath(parts, i);
    const htri_t link = H5Lexists(f.fid, prefix.c_str(), H5P_DEFAULT);
    if (link < 0) fail(f.path, "cannot look up " + sq(prefix) + " while creating " + sq(path));
    if (link == 0) {
      Handle g(H5Gcreate2(f.fid, prefix.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
      if (!g.valid()) fail(f.path, "cannot create group " + sq(prefix) + " for " + sq(path));
      continue;
    }
    const Kind k = kindOfExisting(f, prefix);
    if (k != Kind::Group)
      fail(
          f.path,
          "cannot create " + sq(path) + ": " + sq(prefix) + " is " + kindName(k) + ", not a group; choose another path",
          false);
  }
}

void requireWritable(const FileState& f, const std::string& obj, const char* operation) {
  if (f.mode == Hdf5File::Mode::ReadOnly)
    fail(f.path,
         std::string("cannot ") + operation + " " + sq(obj) +
             ": the file is opened ReadOnly; open it with Hdf5File::Mode::ReadWrite to modify it",
         false);
}

[[noreturn]] void missingDataset(const FileState& f, const std::string& path) {
  fail(f.path, "no dataset " + sq(path) + " (the file may be incomplete or from an older version)", false);
}

/// Writes the buffered records of a series; leaves the buffer intact on failure.
void flushSeries(SeriesState& s) {
  if (s.buffered == 0) return;
  if (s.file == nullptr || !s.dset.valid())
    fail(s.filePath,
         "cannot write " + std::to_string(s.buffered) + " buffered records of series " + sq(s.path) +
             ": the file was closed before the series was flushed; "
             "flush or destroy the Series before closing its Hdf5File",
         false);
  const std::string& file = s.file->path;
  const std::size_t rank = 1 + s.fileRecordDims.size();
  std::vector<hsize_t> newDims(rank), start(rank, 0), count(rank);
  newDims[0] = s.written + s.buffered;
  start[0] = s.written;
  count[0] = s.buffered;
  for (std::size_t i = 1; i < rank; ++i) newDims[i] = count[i] = s.fileRecordDims[i - 1];

  if (H5Dset_extent(s.dset.get(), newDims.data()) < 0)
    fail(file,
         "cannot extend series " + sq(s.path) + " to " + dimsText(newDims) + " (disk full or file not writable?)");
  Handle fspace(H5Dget_space(s.dset.get()), H5Sclose);
  if (!fspace.valid()) fail(file, "cannot get the dataspace of series " + sq(s.path));
  if (H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr) < 0)
    fail(file, "cannot select records " + std::to_string(s.written) + ".." + std::to_string(newDims[0] - 1) +
                   " of series " + sq(s.path));
  Handle mspace(H5Screate_simple(static_cast<int>(rank), count.data(), nullptr), H5Sclose);
  if (!mspace.valid()) fail(file, "cannot create a memory dataspace for series " + sq(s.path));
  if (H5Dwrite(s.dset.get(), H5T_NATIVE_DOUBLE, mspace.get(), fspace.get(), H5P_DEFAULT, s.buffer.data()) < 0)
    fail(file, "cannot write " + std::to_string(s.buffered) + " records to series " + sq(s.path) +
                   " (disk full or file not writable?)");
  s.written = newDims[0];
  s.buffered = 0;
}

/// Flushes the live series writing `path`, so that a read sees every appended record.
void flushSeriesAt(FileState& f, const std::string& path) {
  for (SeriesState* s : f.series)
    if (s->path == path) flushSeries(*s);
}

/// Refuses to replace or reopen a dataset that a live Series is writing.
void requireNoLiveSeries(const FileState& f, const std::string& path, const char* operation) {
  for (const SeriesState* s : f.series)
    if (s->path == path)
      fail(f.path,
           std::string(operation) + " " + sq(path) +
               ": a Series is writing that dataset; destroy the Series first or choose another path",
           false);
}

/// Flushes and detaches every live series, then closes the file. Throws the first error after
/// doing all of it.
void closeFile(FileState& f) {
  if (f.fid < 0) return;
  std::string firstError;
  for (SeriesState* s : f.series) {
    try {
      flushSeries(*s);
    } catch (const std::exception& e) {
      if (firstError.empty()) firstError = e.what();
    }
    s->dset.reset();
    s->file = nullptr;
  }
  f.series.clear();
  const herr_t rc = H5Fclose(f.fid);
  f.fid = H5I_INVALID_HID;
  if (!firstError.empty()) throw Error(firstError);
  if (rc < 0) fail(f.path, "error while closing the file (disk full? the data may be incomplete)");
}

// ---- datasets ------------------------------------------------------------------------------

Handle openDataset(const FileState& f, const std::string& path) {
  const Kind k = kindOf(f, path);
  if (k == Kind::None) missingDataset(f, path);
  if (k != Kind::Dataset)
    fail(f.path,
         sq(path) + " is " + kindName(k) +
             ", not a dataset (the file may be from another "
             "program or an older version)",
         false);
  Handle d(H5Dopen2(f.fid, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) fail(f.path, "cannot open dataset " + sq(path));
  return d;
}

/// The shape of a dataset ({} for a scalar), and its element count.
std::vector<hsize_t> datasetDims(const FileState& f, const std::string& path, hid_t dset, std::uint64_t* count) {
  Handle space(H5Dget_space(dset), H5Sclose);
  if (!space.valid()) fail(f.path, "cannot get the dataspace of " + sq(path));
  std::vector<hsize_t> dims;
  switch (H5Sget_simple_extent_type(space.get())) {
    case H5S_NULL:
      *count = 0;
      return dims;
    case H5S_SCALAR:
      *count = 1;
      return dims;
    case H5S_SIMPLE: {
      const int rank = H5Sget_simple_extent_ndims(space.get());
      if (rank < 0) fail(f.path, "cannot get the rank of " + sq(path));
      dims.resize(static_cast<std::size_t>(rank));
      if (H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
        fail(f.path, "cannot get the shape of " + sq(path));
      *count = elementCount(f.path, path, dims);
      return dims;
    }
    default:
      fail(f.path, "cannot get the dataspace type of " + sq(path));
  }
}

H5T_class_t typeClass(const FileState& f, const std::string& what, hid_t type) {
  const H5T_class_t c = H5Tget_class(type);
  if (c == H5T_NO_CLASS) fail(f.path, "cannot get the datatype class of " + what);
  return c;
}

const char* className(H5T_class_t c) {
  switch (c) {
    case H5T_INTEGER:
      return "integer";
    case H5T_FLOAT:
      return "floating-point";
    case H5T_STRING:
      return "string";
    case H5T_COMPOUND:
      return "compound";
    case H5T_ENUM:
      return "enum";
    case H5T_ARRAY:
      return "array";
    case H5T_VLEN:
      return "variable-length";
    default:
      return "non-numeric";
  }
}

/// Writes a whole numeric array, replacing any dataset at `path`.
void writeArray(FileState& f, const std::string& rawPath, const std::vector<std::uint64_t>& dims64, const void* data,
                hid_t fileType, hid_t memType, const char* operation) {
  const std::string path = normalize(f.path, rawPath);
  requireWritable(f, path, operation);
  if (path == "/") fail(f.path, std::string(operation) + ": '/' is the root group, not a dataset path", false);
  const std::vector<hsize_t> dims(dims64.begin(), dims64.end());
  if (dims.empty() || dims.size() > H5S_MAX_RANK)
    fail(f.path,
         std::string(operation) + " " + sq(path) + ": rank " + std::to_string(dims.size()) +
             " is not supported; give 1 to " + std::to_string(H5S_MAX_RANK) + " dimensions",
         false);
  const std::uint64_t n = elementCount(f.path, path, dims);
  if (n > 0 && data == nullptr)
    fail(f.path, std::string(operation) + " " + sq(path) + ": null data pointer for shape " + dimsText(dims), false);
  requireNoLiveSeries(f, path, operation);
  ensureParents(f, path);

  const Kind k = kindOf(f, path);
  if (k == Kind::Group || k == Kind::Other)
    fail(f.path,
         std::string(operation) + " " + sq(path) + ": it is " + kindName(k) +
             " (an attribute set on a path before the dataset was written creates a group "
             "there); choose another path or write the dataset first",
         false);
  Handle dset;
  if (k == Kind::Dataset) {
    // Same type class and size and same shape: overwrite in place (no file space lost).
    // Otherwise unlink the old dataset and create a new one.
    Handle d(H5Dopen2(f.fid, path.c_str(), H5P_DEFAULT), H5Dclose);
    if (!d.valid()) fail(f.path, "cannot open dataset " + sq(path) + " to replace it");
    Handle type(H5Dget_type(d.get()), H5Tclose);
    if (!type.valid()) fail(f.path, "cannot get the datatype of " + sq(path));
    std::uint64_t oldCount = 0;
    Handle space(H5Dget_space(d.get()), H5Sclose);
    const bool simple = space.valid() && H5Sget_simple_extent_type(space.get()) == H5S_SIMPLE;
    const auto oldDims = datasetDims(f, path, d.get(), &oldCount);
    if (simple && oldDims == dims && H5Tequal(type.get(), fileType) > 0) {
      dset = std::move(d);
    } else {
      d.reset();
      if (H5Ldelete(f.fid, path.c_str(), H5P_DEFAULT) < 0)
        fail(f.path, "cannot remove the old dataset " + sq(path) + " to replace it");
    }
  }
  if (!dset.valid()) {
    Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
    if (!space.valid()) fail(f.path, "cannot create a dataspace of shape " + dimsText(dims) + " for " + sq(path));
    dset =
        Handle(H5Dcreate2(f.fid, path.c_str(), fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
    if (!dset.valid()) fail(f.path, "cannot create dataset " + sq(path) + " of shape " + dimsText(dims));
  }
  if (n > 0 && H5Dwrite(dset.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail(f.path,
         "cannot write dataset " + sq(path) + " of shape " + dimsText(dims) + " (disk full or file not writable?)");
}

template <class T>
std::vector<T> readArray(FileState& f, const std::string& rawPath, std::vector<std::uint64_t>* dimsOut, hid_t memType,
                         bool integersOnly) {
  const std::string path = normalize(f.path, rawPath);
  flushSeriesAt(f, path);
  Handle dset = openDataset(f, path);
  Handle type(H5Dget_type(dset.get()), H5Tclose);
  if (!type.valid()) fail(f.path, "cannot get the datatype of " + sq(path));
  const H5T_class_t c = typeClass(f, sq(path), type.get());
  if (c != H5T_INTEGER && !(c == H5T_FLOAT && !integersOnly))
    fail(f.path,
         "dataset " + sq(path) + " holds " + className(c) + " values, not " +
             (integersOnly ? "integers; read it with readDoubles" : "numbers") +
             (c == H5T_STRING ? " (read it with readString)" : ""),
         false);
  std::uint64_t n = 0;
  const auto dims = datasetDims(f, path, dset.get(), &n);
  if (n > std::numeric_limits<std::size_t>::max() / sizeof(T))
    fail(f.path, "dataset " + sq(path) + " of shape " + dimsText(dims) + " is too large to read", false);
  std::vector<T> values(static_cast<std::size_t>(n));
  if (n > 0 && H5Dread(dset.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
    fail(f.path, "cannot read dataset " + sq(path) + " of shape " + dimsText(dims) +
                     (integersOnly ? " as 64-bit integers (values out of range?)" : " as doubles"));
  if (dimsOut != nullptr) dimsOut->assign(dims.begin(), dims.end());
  return values;
}

/// A string type for `text`: fixed length, null-padded, UTF-8.
Handle stringType(const FileState& f, const std::string& what, std::size_t length) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!t.valid() || H5Tset_size(t.get(), std::max<std::size_t>(length, 1)) < 0 ||
      H5Tset_strpad(t.get(), H5T_STR_NULLPAD) < 0 || H5Tset_cset(t.get(), H5T_CSET_UTF8) < 0)
    fail(f.path, "cannot make a string type of " + std::to_string(length) + " bytes for " + what);
  return t;
}

/// Reads a scalar string from a dataset (isAttribute false) or attribute, fixed or variable length.
std::string readStringFrom(const FileState& f, const std::string& what, hid_t obj, bool isAttribute) {
  Handle type(isAttribute ? H5Aget_type(obj) : H5Dget_type(obj), H5Tclose);
  if (!type.valid()) fail(f.path, "cannot get the datatype of " + what);
  const H5T_class_t c = typeClass(f, what, type.get());
  if (c != H5T_STRING)
    fail(f.path,
         what + " holds " + className(c) + " values, not a string" +
             (c == H5T_FLOAT || c == H5T_INTEGER ? (isAttribute ? "; read it with doubleAttribute or intAttribute"
                                                                : "; read it with readDoubles or readInts")
                                                 : ""),
         false);
  Handle space(isAttribute ? H5Aget_space(obj) : H5Dget_space(obj), H5Sclose);
  if (!space.valid()) fail(f.path, "cannot get the dataspace of " + what);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n != 1) fail(f.path, what + " holds " + std::to_string(n) + " strings, expected one (a scalar)", false);

  const htri_t variable = H5Tis_variable_str(type.get());
  if (variable < 0) fail(f.path, "cannot inspect the string type of " + what);
  if (variable > 0) {
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    if (!mem.valid() || H5Tset_size(mem.get(), H5T_VARIABLE) < 0 || H5Tset_cset(mem.get(), H5Tget_cset(type.get())) < 0)
      fail(f.path, "cannot make a variable-length string type to read " + what);
    char* buf = nullptr;
    const herr_t rc =
        isAttribute ? H5Aread(obj, mem.get(), &buf) : H5Dread(obj, mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &buf);
    if (rc < 0) fail(f.path, "cannot read " + what);
    std::string text = buf != nullptr ? std::string(buf) : std::string();
#if H5_VERSION_GE(1, 12, 0)
    H5Treclaim(mem.get(), space.get(), H5P_DEFAULT, &buf);
#else
    H5Dvlen_reclaim(mem.get(), space.get(), H5P_DEFAULT, &buf);
#endif
    return text;
  }

  const std::size_t size = H5Tget_size(type.get());
  if (size == 0) fail(f.path, "cannot get the string length of " + what);
  const H5T_str_t pad = H5Tget_strpad(type.get());
  Handle mem(H5Tcopy(type.get()), H5Tclose);
  if (!mem.valid()) fail(f.path, "cannot make a string type to read " + what);
  std::string buf(size, '\0');
  const herr_t rc = isAttribute ? H5Aread(obj, mem.get(), buf.data())
                                : H5Dread(obj, mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
  if (rc < 0) fail(f.path, "cannot read " + what);
  if (pad == H5T_STR_NULLTERM) {
    buf.resize(std::min(buf.find('\0'), buf.size()));
  } else {
    const char padChar = pad == H5T_STR_SPACEPAD ? ' ' : '\0';
    buf.erase(buf.find_last_not_of(padChar) + 1);  // npos + 1 == 0: all padding
  }
  return buf;
}

// ---- attributes ------------------------------------------------------------------------------

/// Opens the object carrying attributes, creating a group there if `create` and it is missing.
Handle openAttributeHolder(FileState& f, const std::string& path, const std::string& name, bool create) {
  const Kind k = kindOf(f, path);
  if (k == Kind::None) {
    if (!create)
      fail(f.path,
           "no group or dataset " + sq(path) + " to read attribute " + sq(name) +
               " from (the file may be incomplete or from an older version)",
           false);
    ensureParents(f, path);
    Handle g(H5Gcreate2(f.fid, path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!g.valid()) fail(f.path, "cannot create group " + sq(path) + " for attribute " + sq(name));
  }
  Handle obj(H5Oopen(f.fid, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) fail(f.path, "cannot open " + sq(path) + " for attribute " + sq(name));
  return obj;
}

void checkAttributeName(const FileState& f, const std::string& path, const std::string& name) {
  if (name.empty()) fail(f.path, "empty attribute name on " + sq(path) + "; give a name", false);
}

void writeAttribute(FileState& f, const std::string& rawPath, const std::string& name, hid_t fileType, hid_t memType,
                    const void* value) {
  const std::string path = normalize(f.path, rawPath);
  requireWritable(f, path, ("set attribute " + sq(name) + " on").c_str());
  checkAttributeName(f, path, name);
  Handle obj = openAttributeHolder(f, path, name, true);
  const htri_t exists = H5Aexists(obj.get(), name.c_str());
  if (exists < 0) fail(f.path, "cannot look up attribute " + sq(name) + " of " + sq(path));
  if (exists > 0 && H5Adelete(obj.get(), name.c_str()) < 0)
    fail(f.path, "cannot remove the old attribute " + sq(name) + " of " + sq(path) + " to replace it");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (!space.valid()) fail(f.path, "cannot create a scalar dataspace for attribute " + sq(name));
  Handle attr(H5Acreate2(obj.get(), name.c_str(), fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid())
    fail(f.path, "cannot create attribute " + sq(name) + " on " + sq(path) +
                     " (attributes are limited to 64 KiB; store long text with writeString)");
  if (H5Awrite(attr.get(), memType, value) < 0) fail(f.path, "cannot write attribute " + sq(name) + " on " + sq(path));
}

Handle openAttribute(FileState& f, const std::string& path, const std::string& name, Handle* holder) {
  checkAttributeName(f, path, name);
  *holder = openAttributeHolder(f, path, name, false);
  const htri_t exists = H5Aexists(holder->get(), name.c_str());
  if (exists < 0) fail(f.path, "cannot look up attribute " + sq(name) + " of " + sq(path));
  if (exists == 0)
    fail(f.path, sq(path) + " has no attribute " + sq(name) + " (the file may be incomplete or from an older version)",
         false);
  Handle attr(H5Aopen(holder->get(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) fail(f.path, "cannot open attribute " + sq(name) + " of " + sq(path));
  return attr;
}

/// Reads a one-element numeric attribute into `value` with memory type `memType`.
void readNumericAttribute(FileState& f, const std::string& rawPath, const std::string& name, hid_t memType,
                          bool integersOnly, void* value) {
  const std::string path = normalize(f.path, rawPath);
  Handle holder;
  Handle attr = openAttribute(f, path, name, &holder);
  const std::string what = "attribute " + sq(name) + " of " + sq(path);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  if (!type.valid()) fail(f.path, "cannot get the datatype of " + what);
  const H5T_class_t c = typeClass(f, what, type.get());
  if (c != H5T_INTEGER && !(c == H5T_FLOAT && !integersOnly))
    fail(f.path,
         what + " holds " + className(c) + " values, not " + (integersOnly ? "an integer" : "a number") +
             (c == H5T_STRING ? "; read it with stringAttribute"
                              : (c == H5T_FLOAT ? "; read it with doubleAttribute" : "")),
         false);
  Handle space(H5Aget_space(attr.get()), H5Sclose);
  if (!space.valid()) fail(f.path, "cannot get the dataspace of " + what);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n != 1) fail(f.path, what + " holds " + std::to_string(n) + " values, expected one", false);
  if (H5Aread(attr.get(), memType, value) < 0) fail(f.path, "cannot read " + what);
}

}  // namespace

// ---- Hdf5File ----------------------------------------------------------------------------------

void Hdf5File::checkCreatable(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  fs::path dir = p.parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::exists(dir, ec))
    fail(path,
         "cannot create the file: directory " + sq(dir.string()) + " does not exist; create it (mkdir -p " +
             dir.string() + ") or choose another path",
         false);
  if (!fs::is_directory(dir, ec))
    fail(path, "cannot create the file: " + sq(dir.string()) + " is not a directory", false);
  if (fs::is_directory(p, ec))
    fail(path, "cannot create the file: a directory of that name exists; choose another name", false);
  if (access(dir.c_str(), W_OK) != 0)
    fail(path, "cannot create the file: directory " + sq(dir.string()) + " is not writable; choose another path",
         false);
}

Hdf5File::Hdf5File(const std::string& path, Mode mode) : state_(std::make_unique<FileState>()) {
  silenceHdf5();
  state_->path = path;
  state_->mode = mode;
  if (path.empty()) fail("Hdf5File", "empty file path; give the name of an .h5 file", false);
  std::error_code ec;
  const fs::path p(path);
  if (mode == Mode::Create) {
    checkCreatable(path);
    fs::path dir = p.parent_path();
    if (dir.empty()) dir = ".";
    state_->fid = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (state_->fid < 0)
      fail(path, "cannot create the file: check that directory " + sq(dir.string()) +
                     " is writable (permissions, disk space) and that no other program has the file open "
                     "(HDF5 locks open files; HDF5_USE_FILE_LOCKING=FALSE disables locking on file systems "
                     "without it)");
    return;
  }
  if (!fs::exists(p, ec)) {
    const fs::path cwd = fs::current_path(ec);
    fail(path,
         "no such file; check the path" +
             (p.is_relative() ? " (relative to the working directory " + sq(cwd.string()) + ")" : std::string()),
         false);
  }
  if (fs::is_directory(p, ec)) fail(path, "is a directory, not an HDF5 file", false);
#if H5_VERSION_GE(1, 12, 0)
  const htri_t isHdf5 = H5Fis_accessible(path.c_str(), H5P_DEFAULT);
#else
  const htri_t isHdf5 = H5Fis_hdf5(path.c_str());
#endif
  if (isHdf5 == 0)
    fail(path, "is not an HDF5 file (no HDF5 signature); check the path, or the file was truncated", false);
  if (isHdf5 < 0) fail(path, "cannot read the file; check its permissions");
  state_->fid = H5Fopen(path.c_str(), mode == Mode::ReadOnly ? H5F_ACC_RDONLY : H5F_ACC_RDWR, H5P_DEFAULT);
  if (state_->fid < 0)
    fail(path, std::string("cannot open the file ") + (mode == Mode::ReadOnly ? "for reading" : "for writing") +
                   ": check its permissions and that no other program (or Hdf5File) has it open for writing "
                   "(HDF5 locks open files; HDF5_USE_FILE_LOCKING=FALSE disables locking on file systems "
                   "without it)");
  // HDF5 without SWMR is not crash-consistent between two flushes: a SIGKILL inside a flush can leave
  // on disk a chunk index pointing past the end of allocation (EOA) that the superblock, written
  // later, records ("addr overflow" on reading; about 1 kill in 70 in faults.kill9-storm). The chunk
  // itself is on disk. Opened for writing (a restart), the EOA is raised to the file's end, as
  // `h5clear --increment=0` does, so such a file reads and continues; a sound file loses nothing.
  if (mode == Mode::ReadWrite && H5Fincrement_filesize(state_->fid, 0) < 0)
    fail(path, "cannot set the file's end of allocation to its size (h5clear --increment=0 does it by hand)");
}

Hdf5File::~Hdf5File() {
  if (!state_) return;
  try {
    closeFile(*state_);
  } catch (const std::exception& e) {
    std::cerr << "epaphe::io::Hdf5File: " << e.what() << std::endl;
  }
}

Hdf5File::Hdf5File(Hdf5File&& other) noexcept = default;

Hdf5File& Hdf5File::operator=(Hdf5File&& other) noexcept {
  if (this != &other) {
    Hdf5File old(std::move(*this));  // closes the current file
    state_ = std::move(other.state_);
  }
  return *this;
}

FileState& Hdf5File::state(const char* operation) const {
  if (!state_)
    fail("Hdf5File", std::string(operation) + ": the object was moved from; use the Hdf5File it was moved to", false);
  if (state_->fid < 0)
    fail(state_->path, std::string(operation) + ": the file was closed; open it again with a new Hdf5File", false);
  return *state_;
}

const std::string& Hdf5File::path() const {
  static const std::string none;
  return state_ ? state_->path : none;
}

Hdf5File::Mode Hdf5File::mode() const {
  return state("mode").mode;
}

bool Hdf5File::isOpen() const {
  return state_ && state_->fid >= 0;
}

void Hdf5File::setSeriesCompression(bool on) {
  state("setSeriesCompression").compressSeries = on;
}

void Hdf5File::flush() {
  FileState& f = state("flush");
  for (SeriesState* s : f.series) flushSeries(*s);
  if (f.mode != Mode::ReadOnly && H5Fflush(f.fid, H5F_SCOPE_GLOBAL) < 0)
    fail(f.path, "cannot flush the file to disk (disk full?)");
}

void Hdf5File::close() {
  if (state_) closeFile(*state_);
}

bool Hdf5File::exists(const std::string& objPath) const {
  FileState& f = state("exists");
  return kindOf(f, normalize(f.path, objPath)) != Kind::None;
}

void Hdf5File::setAttribute(const std::string& objPath, const std::string& name, const std::string& value) {
  FileState& f = state("setAttribute");
  Handle type = stringType(f, "attribute " + sq(name), value.size());
  const std::string padded = value.empty() ? std::string(1, '\0') : value;
  writeAttribute(f, objPath, name, type.get(), type.get(), padded.data());
}

void Hdf5File::setAttribute(const std::string& objPath, const std::string& name, const char* value) {
  setAttribute(objPath, name, std::string(value != nullptr ? value : ""));
}

void Hdf5File::setAttribute(const std::string& objPath, const std::string& name, double value) {
  writeAttribute(state("setAttribute"), objPath, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}

void Hdf5File::setAttribute(const std::string& objPath, const std::string& name, long long value) {
  writeAttribute(state("setAttribute"), objPath, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, &value);
}

bool Hdf5File::hasAttribute(const std::string& objPath, const std::string& name) const {
  FileState& f = state("hasAttribute");
  const std::string path = normalize(f.path, objPath);
  if (kindOf(f, path) == Kind::None || name.empty()) return false;
  Handle obj(H5Oopen(f.fid, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) fail(f.path, "cannot open " + sq(path));
  const htri_t exists = H5Aexists(obj.get(), name.c_str());
  if (exists < 0) fail(f.path, "cannot look up attribute " + sq(name) + " of " + sq(path));
  return exists > 0;
}

std::string Hdf5File::stringAttribute(const std::string& objPath, const std::string& name) const {
  FileState& f = state("stringAttribute");
  const std::string path = normalize(f.path, objPath);
  Handle holder;
  Handle attr = openAttribute(f, path, name, &holder);
  return readStringFrom(f, "attribute " + sq(name) + " of " + sq(path), attr.get(), true);
}

double Hdf5File::doubleAttribute(const std::string& objPath, const std::string& name) const {
  double v = 0.0;
  readNumericAttribute(state("doubleAttribute"), objPath, name, H5T_NATIVE_DOUBLE, false, &v);
  return v;
}

long long Hdf5File::intAttribute(const std::string& objPath, const std::string& name) const {
  long long v = 0;
  readNumericAttribute(state("intAttribute"), objPath, name, H5T_NATIVE_LLONG, true, &v);
  return v;
}

void Hdf5File::writeDoubles(const std::string& path, const std::vector<std::uint64_t>& dims, const double* data) {
  writeArray(state("writeDoubles"), path, dims, data, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, "writeDoubles");
}

void Hdf5File::writeDoubles(const std::string& path, const std::vector<double>& values) {
  writeDoubles(path, {values.size()}, values.data());
}

void Hdf5File::writeInts(const std::string& path, const std::vector<std::uint64_t>& dims, const long long* data) {
  writeArray(state("writeInts"), path, dims, data, H5T_STD_I64LE, H5T_NATIVE_LLONG, "writeInts");
}

void Hdf5File::writeInts(const std::string& path, const std::vector<long long>& values) {
  writeInts(path, {values.size()}, values.data());
}

void Hdf5File::writeString(const std::string& rawPath, const std::string& text) {
  FileState& f = state("writeString");
  const std::string path = normalize(f.path, rawPath);
  requireWritable(f, path, "writeString");
  requireNoLiveSeries(f, path, "writeString");
  if (path == "/") fail(f.path, "writeString: '/' is the root group, not a dataset path", false);
  ensureParents(f, path);
  const Kind k = kindOf(f, path);
  if (k == Kind::Group || k == Kind::Other)
    fail(f.path, "writeString " + sq(path) + ": it is " + kindName(k) + "; choose another path", false);
  if (k == Kind::Dataset && H5Ldelete(f.fid, path.c_str(), H5P_DEFAULT) < 0)
    fail(f.path, "cannot remove the old dataset " + sq(path) + " to replace it");
  Handle type = stringType(f, sq(path), text.size());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (!space.valid()) fail(f.path, "cannot create a scalar dataspace for " + sq(path));
  Handle dset(H5Dcreate2(f.fid, path.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Dclose);
  if (!dset.valid()) fail(f.path, "cannot create string dataset " + sq(path));
  const std::string padded = text.empty() ? std::string(1, '\0') : text;
  if (H5Dwrite(dset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()) < 0)
    fail(f.path, "cannot write string dataset " + sq(path) + " (disk full or file not writable?)");
}

std::vector<double> Hdf5File::readDoubles(const std::string& path, std::vector<std::uint64_t>* dims) const {
  return readArray<double>(state("readDoubles"), path, dims, H5T_NATIVE_DOUBLE, false);
}

std::vector<long long> Hdf5File::readInts(const std::string& path, std::vector<std::uint64_t>* dims) const {
  return readArray<long long>(state("readInts"), path, dims, H5T_NATIVE_LLONG, true);
}

std::string Hdf5File::readString(const std::string& rawPath) const {
  FileState& f = state("readString");
  const std::string path = normalize(f.path, rawPath);
  Handle dset = openDataset(f, path);
  return readStringFrom(f, "dataset " + sq(path), dset.get(), false);
}

// ---- Series ------------------------------------------------------------------------------------

namespace {

/// Records per chunk: the buffer size, capped so that a chunk stays within HDF5's default
/// 1 MiB chunk cache.
hsize_t chunkRecords(std::size_t recordSize, std::size_t bufferRecords) {
  const std::size_t cacheBytes = std::size_t(1) << 20;
  const std::size_t fit = std::max<std::size_t>(1, cacheBytes / (recordSize * sizeof(double)));
  return static_cast<hsize_t>(std::min(bufferRecords, fit));
}

/// A series' dataset access without HDF5's chunk cache. Through the cache, each chunk a flush
/// touches is a fresh allocation of up to 1 MiB that HDF5 fills and copies into before it writes it
/// at H5Fflush: on Linux, pages mapped and faulted in at every checkpoint, most of its time.
/// Uncompressed and without a fill value, a chunk larger than the cache is written from the series'
/// buffer straight to its place in the file, one write per chunk a flush touches. (A compressed
/// series keeps the cache: its filters need the whole chunk.)
Handle directAccess(const FileState& f) {
  Handle dapl(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose);
  if (!dapl.valid() || H5Pset_chunk_cache(dapl.get(), 0, 0, H5D_CHUNK_CACHE_W0_DEFAULT) < 0)
    fail(f.path, "cannot make a dataset access property list without chunk cache");
  return dapl;
}

bool deflateAvailable() {
  if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) return false;
  unsigned int config = 0;
  if (H5Zget_filter_info(H5Z_FILTER_DEFLATE, &config) < 0) return false;
  return (config & H5Z_FILTER_CONFIG_ENCODE_ENABLED) != 0;
}

}  // namespace

Series::Series(Hdf5File& file, const std::string& rawPath, std::vector<std::uint64_t> recordDims,
               std::size_t bufferRecords)
    : state_(std::make_unique<SeriesState>()) {
  FileState& f = file.state("Series");
  SeriesState& s = *state_;
  s.filePath = f.path;
  s.path = normalize(f.path, rawPath);
  requireWritable(f, s.path, "create series");
  if (s.path == "/") fail(f.path, "Series: '/' is the root group, not a dataset path", false);
  s.recordDims = std::move(recordDims);
  s.fileRecordDims.assign(s.recordDims.begin(), s.recordDims.end());
  if (s.fileRecordDims.size() + 1 > H5S_MAX_RANK)
    fail(f.path,
         "series " + sq(s.path) + ": record rank " + std::to_string(s.recordDims.size()) + " is too large; at most " +
             std::to_string(H5S_MAX_RANK - 1),
         false);
  for (hsize_t d : s.fileRecordDims)
    if (d == 0)
      fail(f.path,
           "series " + sq(s.path) + ": record shape " + dimsText(s.fileRecordDims) +
               " has a zero dimension; every record dimension must be >= 1",
           false);
  const std::uint64_t rs = elementCount(f.path, s.path, s.fileRecordDims);
  if (rs > (std::uint64_t(1) << 28))
    fail(f.path,
         "series " + sq(s.path) + ": records of shape " + dimsText(s.fileRecordDims) +
             " are too large (more than 2^28 values, the chunk size limit); write them with "
             "writeDoubles instead",
         false);
  s.recordSize = static_cast<std::size_t>(rs);
  if (bufferRecords == 0)
    fail(f.path, "series " + sq(s.path) + ": bufferRecords = 0; give at least 1 (1024 by default)", false);
  s.bufferRecords = bufferRecords;

  const std::size_t rank = 1 + s.fileRecordDims.size();
  ensureParents(f, s.path);
  const Kind k = kindOf(f, s.path);
  if (k == Kind::Group || k == Kind::Other)
    fail(f.path, "series " + sq(s.path) + ": it is " + kindName(k) + "; choose another path", false);
  if (k == Kind::Dataset) {
    // Append to an existing series of the same record shape.
    requireNoLiveSeries(f, s.path, "create series");
    auto open = [&](hid_t dapl) {
      s.dset.reset();
      s.dset = Handle(H5Dopen2(f.fid, s.path.c_str(), dapl), H5Dclose);
      if (!s.dset.valid()) fail(f.path, "cannot open series " + sq(s.path));
    };
    open(H5P_DEFAULT);
    Handle dcpl(H5Dget_create_plist(s.dset.get()), H5Pclose);
    if (dcpl.valid() && H5Pget_nfilters(dcpl.get()) == 0) open(directAccess(f).get());  // uncompressed
    Handle space(H5Dget_space(s.dset.get()), H5Sclose);
    Handle type(H5Dget_type(s.dset.get()), H5Tclose);
    if (!space.valid() || !type.valid()) fail(f.path, "cannot inspect dataset " + sq(s.path));
    const int r = H5Sget_simple_extent_ndims(space.get());
    std::vector<hsize_t> dims(rank), maxDims(rank);
    const bool sameRank = r == static_cast<int>(rank);
    if (sameRank && H5Sget_simple_extent_dims(space.get(), dims.data(), maxDims.data()) < 0)
      fail(f.path, "cannot get the shape of " + sq(s.path));
    const bool sameRecord = sameRank && std::equal(dims.begin() + 1, dims.end(), s.fileRecordDims.begin());
    if (!sameRecord || maxDims[0] != H5S_UNLIMITED || H5Tget_class(type.get()) != H5T_FLOAT)
      fail(f.path,
           "series " + sq(s.path) + ": a dataset " +
               (sameRank ? "of shape " + dimsText(dims) + " (max " + dimsText(maxDims) + ")"
                         : "of rank " + std::to_string(r)) +
               " is already there and is no series of records " + dimsText(s.fileRecordDims) +
               " of doubles; choose another path or create the file anew",
           false);
    s.written = dims[0];
  } else {
    std::vector<hsize_t> dims(rank), maxDims(rank), chunk(rank);
    dims[0] = 0;
    maxDims[0] = H5S_UNLIMITED;
    chunk[0] = chunkRecords(s.recordSize, s.bufferRecords);
    for (std::size_t i = 1; i < rank; ++i) dims[i] = maxDims[i] = chunk[i] = s.fileRecordDims[i - 1];
    Handle space(H5Screate_simple(static_cast<int>(rank), dims.data(), maxDims.data()), H5Sclose);
    if (!space.valid()) fail(f.path, "cannot create an extendable dataspace for series " + sq(s.path));
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    if (!dcpl.valid() || H5Pset_chunk(dcpl.get(), static_cast<int>(rank), chunk.data()) < 0)
      fail(f.path, "cannot set chunks " + dimsText(chunk) + " for series " + sq(s.path));
    const bool compress = f.compressSeries && deflateAvailable();
    if (compress && (H5Pset_shuffle(dcpl.get()) < 0 || H5Pset_deflate(dcpl.get(), 1) < 0))
      fail(f.path, "cannot set compression for series " + sq(s.path));
    // Uncompressed, no fill value: a chunk's records are all written before the extent shows them
    // (see directAccess).
    if (!compress && H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER) < 0)
      fail(f.path, "cannot set the fill time of series " + sq(s.path));
    s.dset = Handle(H5Dcreate2(f.fid, s.path.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, dcpl.get(),
                               compress ? H5P_DEFAULT : directAccess(f).get()),
                    H5Dclose);
    if (!s.dset.valid()) fail(f.path, "cannot create series dataset " + sq(s.path));
  }
  s.buffer.resize(s.bufferRecords * s.recordSize);
  s.file = &f;
  f.series.push_back(&s);
}

namespace {

/// Flushes (reporting errors on stderr) and detaches a series from its file.
void releaseSeries(SeriesState& s) noexcept {
  if (s.file == nullptr) return;
  try {
    flushSeries(s);
  } catch (const std::exception& e) {
    std::cerr << "epaphe::io::Series: " << e.what() << std::endl;
  }
  s.dset.reset();
  auto& list = s.file->series;
  list.erase(std::remove(list.begin(), list.end(), &s), list.end());
  s.file = nullptr;
}

}  // namespace

Series::~Series() {
  if (state_) releaseSeries(*state_);
}

Series::Series(Series&& other) noexcept = default;

Series& Series::operator=(Series&& other) noexcept {
  if (this != &other) {
    if (state_) releaseSeries(*state_);
    state_ = std::move(other.state_);
  }
  return *this;
}

SeriesState& Series::state(const char* operation) const {
  if (!state_)
    fail("Series", std::string(operation) + ": the object was moved from; use the Series it was moved to", false);
  return *state_;
}

void Series::append(const double* record) {
  SeriesState& s = state("append");
  if (s.file == nullptr)
    fail(s.filePath,
         "cannot append to series " + sq(s.path) +
             ": its Hdf5File was closed; keep the file open while the series is in use",
         false);
  if (record == nullptr) fail(s.filePath, "append to series " + sq(s.path) + ": null record pointer", false);
  std::copy(record, record + s.recordSize, s.buffer.begin() + static_cast<std::ptrdiff_t>(s.buffered * s.recordSize));
  ++s.buffered;
  if (s.buffered == s.bufferRecords) flushSeries(s);
}

void Series::append(const std::vector<double>& record) {
  SeriesState& s = state("append");
  if (record.size() != s.recordSize)
    fail(s.filePath,
         "append to series " + sq(s.path) + ": record has " + std::to_string(record.size()) + " values, expected " +
             std::to_string(s.recordSize) + " (record shape " + dimsText(s.fileRecordDims) + ")",
         false);
  append(record.data());
}

std::size_t Series::recordSize() const {
  return state("recordSize").recordSize;
}

std::size_t Series::size() const {
  const SeriesState& s = state("size");
  return static_cast<std::size_t>(s.written) + s.buffered;
}

const std::vector<std::uint64_t>& Series::recordDims() const {
  return state("recordDims").recordDims;
}

const std::string& Series::path() const {
  return state("path").path;
}

void Series::flush() {
  flushSeries(state("flush"));
}

void Series::truncate(std::size_t records) {
  SeriesState& s = state("truncate");
  if (s.file == nullptr) fail(s.filePath, "cannot truncate series " + sq(s.path) + ": its Hdf5File was closed", false);
  const std::size_t total = static_cast<std::size_t>(s.written) + s.buffered;
  if (records > total)
    fail(s.filePath,
         "cannot truncate series " + sq(s.path) + " to " + std::to_string(records) + " records: it holds " +
             std::to_string(total) + " (the file is shorter than its checkpoint)",
         false);
  if (records >= s.written) {  // only buffered records go
    s.buffered = records - static_cast<std::size_t>(s.written);
    return;
  }
  s.buffered = 0;
  const std::size_t rank = 1 + s.fileRecordDims.size();
  std::vector<hsize_t> newDims(rank);
  newDims[0] = records;
  for (std::size_t i = 1; i < rank; ++i) newDims[i] = s.fileRecordDims[i - 1];
  if (H5Dset_extent(s.dset.get(), newDims.data()) < 0)
    fail(s.filePath, "cannot shrink series " + sq(s.path) + " to " + dimsText(newDims));
  s.written = records;
}

}  // namespace epaphe::io
