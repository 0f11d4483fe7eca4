#pragma once
// HDF5 files for Epaphe: attributes, whole arrays and buffered time series.
//
// Thin layer over the HDF5 C API (kept out of this header). A file is used serially, from one
// MPI rank, with the default file access properties. Every failure throws epaphe::Error naming
// the file, the object path, the value seen and what to do; HDF5's own error-stack printing is
// switched off and its description is appended to the message instead.
//
// Object paths are slash paths from the root: "/contact/gap" (a missing leading slash is
// accepted, "contact/gap" is the same object). Writing creates the missing parent groups.
// Arrays are row-major (C order), stored as 64-bit little-endian doubles / integers.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

/// HDF5 output and input: files, attributes, whole arrays and buffered time series (Hdf5File, Series).
namespace epaphe::io {

namespace detail {
struct FileState;
struct SeriesState;
}  // namespace detail

class Series;

/// An HDF5 file: attributes, whole arrays and the Series written to it (see the file's opening comment).
class Hdf5File {
public:
  /// How the constructor opens the file.
  enum class Mode {
    Create,    ///< create, or truncate an existing file
    ReadOnly,  ///< open an existing file for reading
    ReadWrite  ///< open an existing file for reading and writing
  };

  /// Opens or creates `path`. Errors: directory missing or unwritable (Create), file missing,
  /// not an HDF5 file, file locked by another program.
  Hdf5File(const std::string& path, Mode mode);
  /// Throws the error Create would for `path` (directory missing, not a directory, not writable, a
  /// directory of that name), without creating anything: for checks made before any work.
  static void checkCreatable(const std::string& path);
  /// Flushes the live Series of this file, then closes it. Never throws (errors go to stderr;
  /// call close() to see them as exceptions).
  ~Hdf5File();
  /// Takes over the open file of `other`, which is left closed.
  Hdf5File(Hdf5File&& other) noexcept;
  /// Closes this file (as the destructor does) and takes over the open file of `other`.
  Hdf5File& operator=(Hdf5File&& other) noexcept;
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  /// The file's path, as given to the constructor.
  const std::string& path() const;
  /// The mode it was opened with.
  Mode mode() const;
  /// False after close() or a move from this object.
  bool isOpen() const;

  /// Writes the buffered records of every live Series of this file, then flushes HDF5's
  /// caches to disk.
  void flush();
  /// Whether Series created from now on compress their chunks (default: yes). A compressed chunk
  /// written again (a partial chunk flushed, then completed) may move or change size, so a process
  /// killed during that write can leave records already flushed unreadable; an uncompressed chunk
  /// is rewritten in place with the same bytes for the records it held.
  void setSeriesCompression(bool on);
  /// Like the destructor, but throws on failure. Any later use of the object throws; the
  /// Series still attached to it can no longer append.
  void close();

  /// True if a group or dataset exists at `objPath` ("/" always exists).
  bool exists(const std::string& objPath) const;

  // ---- attributes on a group or dataset ("/" for the root) ---------------------------------
  // Setting an attribute on a missing path creates a group there; setting an existing
  // attribute replaces it (its type may change).
  /// Sets attribute `name` of the group or dataset `objPath` ("/" for the root) to `value`: a string, a
  /// double or a 64-bit integer. A missing `objPath` becomes a group; an existing attribute is replaced.
  ///@{
  void setAttribute(const std::string& objPath, const std::string& name, const std::string& value);
  void setAttribute(const std::string& objPath, const std::string& name, const char* value);
  void setAttribute(const std::string& objPath, const std::string& name, double value);
  void setAttribute(const std::string& objPath, const std::string& name, long long value);
  ///@}
  /// Any other integer type is stored as a 64-bit integer (avoids int -> double/long long ambiguity).
  template <class T, std::enable_if_t<
                         std::is_integral_v<T> && !std::is_same_v<T, bool> && !std::is_same_v<T, long long>, int> = 0>
  void setAttribute(const std::string& objPath, const std::string& name, T value) {
    setAttribute(objPath, name, static_cast<long long>(value));
  }
  /// True if the group or dataset `objPath` has an attribute `name`.
  bool hasAttribute(const std::string& objPath, const std::string& name) const;
  /// Reads a string attribute (an Error if it is missing or not a string).
  std::string stringAttribute(const std::string& objPath, const std::string& name) const;
  /// Also reads integer attributes (converted).
  double doubleAttribute(const std::string& objPath, const std::string& name) const;
  /// Integer attributes only: a floating-point attribute is an error, not a truncation.
  long long intAttribute(const std::string& objPath, const std::string& name) const;

  // ---- whole arrays (row-major), rank 1 to 32 ----------------------------------------------
  // Writing an existing dataset replaces it. `data` holds the product of `dims` values (may be
  // null when that product is 0).
  /// Writes a whole array of doubles or integers at `path`, of shape `dims` (row-major; `data` holds
  /// their product of values), or of rank 1 from a vector. An existing dataset is replaced.
  ///@{
  void writeDoubles(const std::string& path, const std::vector<std::uint64_t>& dims, const double* data);
  void writeDoubles(const std::string& path, const std::vector<double>& values);  // rank 1
  void writeInts(const std::string& path, const std::vector<std::uint64_t>& dims, const long long* data);
  void writeInts(const std::string& path, const std::vector<long long>& values);  // rank 1
  ///@}
  /// A text as one scalar string dataset (e.g. the input deck).
  void writeString(const std::string& path, const std::string& text);

  /// Reads a whole dataset of floating-point or integer values (converted to double); `dims`
  /// receives its shape ({} for a scalar). A Series is read with this too: its buffered records
  /// are flushed first, and the shape is {records, recordDims...}.
  std::vector<double> readDoubles(const std::string& path, std::vector<std::uint64_t>* dims = nullptr) const;
  /// Reads a whole dataset of integers (a floating-point dataset is an error).
  std::vector<long long> readInts(const std::string& path, std::vector<std::uint64_t>* dims = nullptr) const;
  /// Reads a scalar string dataset (fixed- or variable-length).
  std::string readString(const std::string& path) const;

private:
  friend class Series;
  detail::FileState& state(const char* operation) const;
  std::unique_ptr<detail::FileState> state_;
};

/// Time series: an extendable, chunked dataset of doubles whose first dimension is the record
/// index, each record of the fixed shape `recordDims` (empty = one scalar per record). Chunks are
/// compressed (shuffle + deflate level 1) when the HDF5 library has deflate and the file's
/// setSeriesCompression is on; uncompressed, a flush writes the records straight to their place in
/// the file (no chunk cache, no fill value).
///
/// Buffered: appended records are kept in memory and written in blocks of `bufferRecords`;
/// flush() writes what is buffered, and so do the destructor, Hdf5File::flush(), close() and
/// the file's destructor (a Series may outlive its file: it can then no longer append).
///
/// If the dataset already exists (file opened ReadWrite) with the same record shape, records
/// are appended after the ones it holds.
class Series {
public:
  /// Attaches to the dataset `path` of `file`, created when missing (records of shape `recordDims`),
  /// or appended to when it exists with that shape; records are written in blocks of `bufferRecords`.
  Series(Hdf5File& file, const std::string& path, std::vector<std::uint64_t> recordDims,
         std::size_t bufferRecords = 1024);
  ~Series();
  /// Takes over the dataset and the buffered records of `other`.
  Series(Series&& other) noexcept;
  /// Flushes this series, then takes over the dataset and the buffered records of `other`.
  Series& operator=(Series&& other) noexcept;
  Series(const Series&) = delete;
  Series& operator=(const Series&) = delete;

  /// Appends one record of recordSize() doubles.
  void append(const double* record);
  /// Same, checking that `record` has recordSize() values.
  void append(const std::vector<double>& record);
  /// Values per record (product of recordDims, 1 for a scalar series).
  std::size_t recordSize() const;
  /// Records in the series: those already in the file plus those buffered.
  std::size_t size() const;
  /// The shape of one record ({} for a scalar series).
  const std::vector<std::uint64_t>& recordDims() const;
  /// The dataset's path in the file.
  const std::string& path() const;
  /// Writes the buffered records to the dataset.
  void flush();
  /// Keeps the first `records` records and drops the others (buffered or in the file; the
  /// dataset shrinks). Used to restart a run from a checkpoint. `records` > size() is an error.
  void truncate(std::size_t records);

private:
  detail::SeriesState& state(const char* operation) const;
  std::unique_ptr<detail::SeriesState> state_;
};

}  // namespace epaphe::io
