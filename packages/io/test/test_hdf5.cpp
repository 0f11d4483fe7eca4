// Unit tests of epaphe::io (HDF5 files). Files are written into the working directory.
#include "Epaphe_Error.hpp"
#include "Epaphe_Hdf5File.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

using epaphe::Error;
using epaphe::io::Hdf5File;
using epaphe::io::Series;
using Dims = std::vector<std::uint64_t>;

namespace {

/// A fresh file name per test, removed before the test.
std::string fileFor(const std::string& name) {
  const std::string path = "io_" + name + ".h5";
  std::remove(path.c_str());
  return path;
}

/// Runs `f`, expects an epaphe::Error and returns its message.
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected epaphe::Error, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected epaphe::Error, nothing thrown";
  return {};
}

std::vector<double> ramp(std::size_t n, double scale) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = scale * static_cast<double>(i) + 0.25;
  return v;
}

}  // namespace

TEST(Hdf5File, RoundTripArraysStringsAttributes) {
  const std::string path = fileFor("roundtrip");
  const auto d1 = ramp(7, 1.5);
  const auto d2 = ramp(3 * 5, -2.0);
  const auto d3 = ramp(2 * 3 * 4, 1e-3);
  std::vector<long long> i1 = {1, -2, 3, 4000000000000LL};
  std::vector<long long> i2(4 * 2), i3(2 * 2 * 3);
  for (std::size_t k = 0; k < i2.size(); ++k) i2[k] = static_cast<long long>(k) - 3;
  for (std::size_t k = 0; k < i3.size(); ++k) i3[k] = static_cast<long long>(k * k);
  const std::string deck = "# deck\nTime step = 1e-4\n\xCE\xB5\xCF\x80\xCE\xB1\xCF\x86\xCE\xAE\n";
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    EXPECT_EQ(f.path(), path);
    f.writeDoubles("/a/rank1", {7}, d1.data());
    f.writeDoubles("/a/b/rank2", {3, 5}, d2.data());
    f.writeDoubles("rank3", {2, 3, 4}, d3.data());  // no leading slash: from the root
    f.writeInts("/ints/rank1", i1);
    f.writeInts("/ints/rank2", {4, 2}, i2.data());
    f.writeInts("/ints/rank3", {2, 2, 3}, i3.data());
    f.writeString("/input/deck", deck);
    f.writeString("/input/empty", "");
    f.writeDoubles("/empty", {0}, nullptr);
    f.setAttribute("/", "title", "test run");
    f.setAttribute("/", "version", 3);
    f.setAttribute("/a/b/rank2", "dt", 1e-4);
    f.setAttribute("/a/b/rank2", "steps", 123456789012LL);
    f.setAttribute("/a", "count", std::size_t(42));
    f.setAttribute("/meta/run", "solver", std::string("newmark"));  // creates the group
    f.setAttribute("/a", "replaced", 1.0);
    f.setAttribute("/a", "replaced", "now a string");
    EXPECT_TRUE(f.exists("/a"));
    EXPECT_TRUE(f.exists("/a/b/rank2"));
    EXPECT_TRUE(f.exists("/meta/run"));
    EXPECT_FALSE(f.exists("/a/nothing"));
    EXPECT_FALSE(f.exists("/a/rank1/below_a_dataset"));
  }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  Dims dims;
  EXPECT_EQ(f.readDoubles("/a/rank1", &dims), d1);
  EXPECT_EQ(dims, Dims({7}));
  EXPECT_EQ(f.readDoubles("/a/b/rank2", &dims), d2);
  EXPECT_EQ(dims, Dims({3, 5}));
  EXPECT_EQ(f.readDoubles("/rank3", &dims), d3);
  EXPECT_EQ(dims, Dims({2, 3, 4}));
  EXPECT_EQ(f.readInts("/ints/rank1", &dims), i1);
  EXPECT_EQ(dims, Dims({4}));
  EXPECT_EQ(f.readInts("/ints/rank2", &dims), i2);
  EXPECT_EQ(dims, Dims({4, 2}));
  EXPECT_EQ(f.readInts("/ints/rank3", &dims), i3);
  EXPECT_EQ(dims, Dims({2, 2, 3}));
  EXPECT_TRUE(f.readDoubles("/empty", &dims).empty());
  EXPECT_EQ(dims, Dims({0}));
  // Integers read as doubles.
  EXPECT_EQ(f.readDoubles("/ints/rank2")[7], 4.0);
  EXPECT_EQ(f.readString("/input/deck"), deck);
  EXPECT_EQ(f.readString("/input/empty"), "");
  EXPECT_EQ(f.stringAttribute("/", "title"), "test run");
  EXPECT_EQ(f.intAttribute("/", "version"), 3);
  EXPECT_EQ(f.doubleAttribute("/a/b/rank2", "dt"), 1e-4);
  EXPECT_EQ(f.intAttribute("/a/b/rank2", "steps"), 123456789012LL);
  EXPECT_EQ(f.doubleAttribute("/a/b/rank2", "steps"), 123456789012.0);
  EXPECT_EQ(f.intAttribute("/a", "count"), 42);
  EXPECT_EQ(f.stringAttribute("/meta/run", "solver"), "newmark");
  EXPECT_EQ(f.stringAttribute("/a", "replaced"), "now a string");
  EXPECT_TRUE(f.hasAttribute("/a", "count"));
  EXPECT_FALSE(f.hasAttribute("/a", "nope"));
  EXPECT_FALSE(f.hasAttribute("/nowhere", "count"));
}

TEST(Hdf5File, OverwriteDatasetsAndReadWrite) {
  const std::string path = fileFor("overwrite");
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    f.writeDoubles("/x", {3}, ramp(3, 1.0).data());
    f.writeDoubles("/x", {3}, ramp(3, 2.0).data());  // same shape: in place
    f.writeDoubles("/y", {2}, ramp(2, 1.0).data());
    f.writeDoubles("/y", {2, 2}, ramp(4, 3.0).data());  // new shape: replaced
    f.writeString("/s", "first");
    f.writeString("/s", "second, longer");
  }
  {
    Hdf5File f(path, Hdf5File::Mode::ReadWrite);
    EXPECT_EQ(f.readDoubles("/x"), ramp(3, 2.0));
    f.writeInts("/z", {1LL, 2LL});
    f.setAttribute("/x", "unit", "m");
  }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  Dims dims;
  EXPECT_EQ(f.readDoubles("/y", &dims), ramp(4, 3.0));
  EXPECT_EQ(dims, Dims({2, 2}));
  EXPECT_EQ(f.readString("/s"), "second, longer");
  EXPECT_EQ(f.readInts("/z"), std::vector<long long>({1, 2}));
  EXPECT_EQ(f.stringAttribute("/x", "unit"), "m");
}

TEST(Hdf5File, CreateTruncates) {
  const std::string path = fileFor("truncate");
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    f.writeDoubles("/old", {1}, ramp(1, 1.0).data());
  }
  Hdf5File f(path, Hdf5File::Mode::Create);
  EXPECT_FALSE(f.exists("/old"));
}

TEST(Hdf5File, MoveKeepsTheFileOpen) {
  const std::string path = fileFor("move");
  Hdf5File a(path, Hdf5File::Mode::Create);
  Series s(a, "/t", {}, 4);
  for (int i = 0; i < 10; ++i) s.append(std::vector<double>{double(i)});
  Hdf5File b(std::move(a));
  EXPECT_FALSE(a.isOpen());
  EXPECT_TRUE(b.isOpen());
  EXPECT_EQ(b.path(), path);
  const std::string msg = errorOf([&] { a.writeInts("/x", {1LL}); });
  EXPECT_NE(msg.find("moved from"), std::string::npos) << msg;
  s.append(std::vector<double>{10.0});
  EXPECT_EQ(b.readDoubles("/t"), std::vector<double>({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
  Hdf5File c(fileFor("move2"), Hdf5File::Mode::Create);
  c = std::move(b);  // closes move2, takes over the file and its series
  EXPECT_EQ(c.path(), path);
  s.append(std::vector<double>{11.0});
  EXPECT_EQ(c.readDoubles("/t").size(), 12u);
}

TEST(Series, TenThousandRecordsOfShape4x3) {
  const std::string path = fileFor("series");
  const std::size_t n = 10000;
  auto value = [](std::size_t r, std::size_t i, std::size_t j) {
    return static_cast<double>(r) * 1.0e-3 + static_cast<double>(i) * 10.0 + static_cast<double>(j) + 1.0 / 3.0;
  };
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    Series s(f, "/contact/gap", {4, 3}, 100);
    EXPECT_EQ(s.recordSize(), 12u);
    std::vector<double> rec(12);
    for (std::size_t r = 0; r < n; ++r) {
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = 0; j < 3; ++j) rec[i * 3 + j] = value(r, i, j);
      s.append(rec.data());
      ASSERT_EQ(s.size(), r + 1);
    }
    s.flush();
    f.flush();
  }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  Dims dims;
  const auto data = f.readDoubles("/contact/gap", &dims);
  ASSERT_EQ(dims, Dims({n, 4, 3}));
  ASSERT_EQ(data.size(), n * 12);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 3; ++j)
        ASSERT_EQ(data[(r * 4 + i) * 3 + j], value(r, i, j)) << "record " << r << " [" << i << "][" << j << "]";
}

TEST(Series, ScalarSeriesIsChunkedExtendableAndCompressed) {
  const std::string path = fileFor("scalar");
  const auto values = ramp(1037, 0.5);  // not a multiple of the buffer
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    Series s(f, "/energy/kinetic", {}, 64);
    EXPECT_EQ(s.recordSize(), 1u);
    for (double v : values) s.append(&v);
    EXPECT_EQ(s.size(), values.size());
  }
  {
    Hdf5File f(path, Hdf5File::Mode::ReadOnly);
    Dims dims;
    EXPECT_EQ(f.readDoubles("/energy/kinetic", &dims), values);
    EXPECT_EQ(dims, Dims({values.size()}));
  }
  // The layout, checked with the HDF5 API.
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t dset = H5Dopen2(file, "/energy/kinetic", H5P_DEFAULT);
  ASSERT_GE(dset, 0);
  const hid_t space = H5Dget_space(dset);
  hsize_t cur = 0, max = 0;
  EXPECT_EQ(H5Sget_simple_extent_dims(space, &cur, &max), 1);
  EXPECT_EQ(cur, values.size());
  EXPECT_EQ(max, H5S_UNLIMITED);
  const hid_t dcpl = H5Dget_create_plist(dset);
  EXPECT_EQ(H5Pget_layout(dcpl), H5D_CHUNKED);
  hsize_t chunk = 0;
  EXPECT_EQ(H5Pget_chunk(dcpl, 1, &chunk), 1);
  EXPECT_EQ(chunk, 64u);
  if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    bool deflate = false;
    for (int i = 0; i < H5Pget_nfilters(dcpl); ++i) {
      unsigned flags = 0, level = 0;
      size_t nelem = 1;
      if (H5Pget_filter2(dcpl, static_cast<unsigned>(i), &flags, &nelem, &level, 0, nullptr, nullptr) ==
          H5Z_FILTER_DEFLATE) {
        deflate = true;
        EXPECT_EQ(level, 1u);
      }
    }
    EXPECT_TRUE(deflate);
  }
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Dclose(dset);
  H5Fclose(file);
}

TEST(Series, FileClosedWithoutExplicitFlushKeepsAllRecords) {
  const std::string path = fileFor("noflush");
  {
    // Series destroyed first, then the file: no flush() anywhere.
    Hdf5File f(path, Hdf5File::Mode::Create);
    Series s(f, "/a", {2}, 1000);
    for (int r = 0; r < 250; ++r) s.append(std::vector<double>{double(r), -double(r)});
  }
  {
    Hdf5File f(path, Hdf5File::Mode::ReadOnly);
    Dims dims;
    const auto a = f.readDoubles("/a", &dims);
    ASSERT_EQ(dims, Dims({250, 2}));
    for (int r = 0; r < 250; ++r) {
      EXPECT_EQ(a[2 * r], double(r));
      EXPECT_EQ(a[2 * r + 1], -double(r));
    }
  }
  // The file destroyed while the Series is alive: the file's destructor writes the buffer, and
  // the Series can then no longer append.
  const std::string path2 = fileFor("noflush2");
  auto f = std::make_unique<Hdf5File>(path2, Hdf5File::Mode::Create);
  Series s(*f, "/b", {}, 1000);
  for (int r = 0; r < 333; ++r) s.append(std::vector<double>{double(r)});
  f.reset();
  const std::string msg = errorOf([&] { s.append(std::vector<double>{1.0}); });
  EXPECT_NE(msg.find(path2), std::string::npos) << msg;
  EXPECT_NE(msg.find("/b"), std::string::npos) << msg;
  Hdf5File g(path2, Hdf5File::Mode::ReadOnly);
  EXPECT_EQ(g.readDoubles("/b").size(), 333u);
}

TEST(Series, ReadSeesBufferedRecordsAndReadWriteAppends) {
  const std::string path = fileFor("append");
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    Series s(f, "/t", {}, 1000);
    for (int r = 0; r < 5; ++r) s.append(std::vector<double>{double(r)});
    EXPECT_EQ(f.readDoubles("/t").size(), 5u);  // flushed for the read
    s.append(std::vector<double>{5.0});
    EXPECT_EQ(s.size(), 6u);
  }
  {
    Hdf5File f(path, Hdf5File::Mode::ReadWrite);
    Series s(f, "/t", {}, 3);
    EXPECT_EQ(s.size(), 6u);
    for (int r = 6; r < 10; ++r) s.append(std::vector<double>{double(r)});
    EXPECT_EQ(s.size(), 10u);
    const std::string msg = errorOf([&] { Series other(f, "/t", {2}); });
    EXPECT_NE(msg.find("Series is writing"), std::string::npos) << msg;
  }
  {
    Hdf5File f(path, Hdf5File::Mode::ReadWrite);
    const std::string msg = errorOf([&] { Series wrong(f, "/t", {2}); });
    EXPECT_NE(msg.find("'/t'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("choose another path"), std::string::npos) << msg;
  }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  EXPECT_EQ(f.readDoubles("/t"), std::vector<double>({0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
}

TEST(Series, TruncateDropsRecordsInTheFileAndBuffered) {
  const std::string path = fileFor("truncate");
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    Series s(f, "/t", {2}, 4);
    for (int r = 0; r < 10; ++r) s.append(std::vector<double>{double(r), -double(r)});  // 8 written, 2 buffered
    s.truncate(9);                                                                      // within the buffer
    EXPECT_EQ(s.size(), 9u);
    s.truncate(6);  // within the file
    EXPECT_EQ(s.size(), 6u);
    s.append(std::vector<double>{60, -60});
    const std::string msg = errorOf([&] { s.truncate(8); });
    EXPECT_NE(msg.find("holds 7"), std::string::npos) << msg;
  }
  {  // a checkpoint restart: reopen, cut, append
    Hdf5File f(path, Hdf5File::Mode::ReadWrite);
    Series s(f, "/t", {2});
    s.truncate(3);
    s.append(std::vector<double>{30, -30});
  }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  std::vector<std::uint64_t> dims;
  EXPECT_EQ(f.readDoubles("/t", &dims), std::vector<double>({0, 0, 1, -1, 2, -2, 30, -30}));
  EXPECT_EQ(dims, std::vector<std::uint64_t>({4, 2}));
}

// Uncompressed, a series is written straight to the file (no chunk cache, no fill value): records
// flushed at any count, so that a flush starts and ends inside chunks, cut by a restart and appended
// to again, read back whole and in order.
TEST(Series, UncompressedFlushesAtAnyRecordAndRestarts) {
  const std::string path = fileFor("direct");
  auto rec = [](int r) { return std::vector<double>{double(r), -0.5 * double(r), 1.0 / (r + 3.0)}; };
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    f.setSeriesCompression(false);
    Series s(f, "/bodies/b/force", {3}, 8);  // chunks of 8 records
    for (int r = 0; r < 29; ++r) {
      s.append(rec(r));
      if (r == 2 || r == 12 || r == 13 || r == 22) f.flush();  // flushes of 3, 10, 1 and 9 records
    }
    EXPECT_EQ(s.size(), 29u);
  }
  {  // a checkpoint restart: reopen, cut inside a chunk, append past the next chunk
    Hdf5File f(path, Hdf5File::Mode::ReadWrite);
    Series s(f, "/bodies/b/force", {3}, 8);
    ASSERT_EQ(s.size(), 29u);
    s.truncate(11);
    for (int r = 11; r < 26; ++r) s.append(rec(100 + r));
  }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  Dims dims;
  const auto data = f.readDoubles("/bodies/b/force", &dims);
  ASSERT_EQ(dims, Dims({26, 3}));
  for (int r = 0; r < 26; ++r) {
    const auto want = rec(r < 11 ? r : 100 + r);
    for (int i = 0; i < 3; ++i) ASSERT_EQ(data[3 * r + i], want[i]) << "record " << r << ", value " << i;
  }
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t dset = H5Dopen2(file, "/bodies/b/force", H5P_DEFAULT);
  ASSERT_GE(dset, 0);
  const hid_t dcpl = H5Dget_create_plist(dset);
  EXPECT_EQ(H5Pget_nfilters(dcpl), 0);
  H5D_fill_time_t fill = H5D_FILL_TIME_ALLOC;
  EXPECT_GE(H5Pget_fill_time(dcpl, &fill), 0);
  EXPECT_EQ(fill, H5D_FILL_TIME_NEVER);
  H5Pclose(dcpl);
  H5Dclose(dset);
  H5Fclose(file);
}

TEST(Errors, OpeningAMissingFile) {
  const std::string path = fileFor("does_not_exist");
  for (auto mode : {Hdf5File::Mode::ReadOnly, Hdf5File::Mode::ReadWrite}) {
    const std::string msg = errorOf([&] { Hdf5File f(path, mode); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
  }
}

TEST(Errors, CreatingInAMissingDirectory) {
  const std::string path = "io_missing_dir/sub/out.h5";
  const std::string msg = errorOf([&] { Hdf5File f(path, Hdf5File::Mode::Create); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("'io_missing_dir/sub'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("create it"), std::string::npos) << msg;
}

TEST(Errors, NotAnHdf5File) {
  const std::string path = "io_not_hdf5.h5";
  { std::ofstream(path) << "this is a deck, not HDF5\n"; }
  const std::string msg = errorOf([&] { Hdf5File f(path, Hdf5File::Mode::ReadOnly); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("not an HDF5 file"), std::string::npos) << msg;
}

TEST(Errors, ReadingMissingObjects) {
  const std::string path = fileFor("missing");
  {
    Hdf5File f(path, Hdf5File::Mode::Create);
    f.writeDoubles("/d", {2}, ramp(2, 1.0).data());
    f.setAttribute("/d", "unit", "m");
  }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  std::string msg = errorOf([&] { f.readDoubles("/x"); });
  EXPECT_EQ(msg, path + ": no dataset '/x' (the file may be incomplete or from an older version)");
  msg = errorOf([&] { f.readInts("/group/x"); });
  EXPECT_NE(msg.find("'/group/x'"), std::string::npos) << msg;
  msg = errorOf([&] { f.readString("/d/below"); });
  EXPECT_NE(msg.find("'/d/below'"), std::string::npos) << msg;
  msg = errorOf([&] { f.doubleAttribute("/d", "nope"); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("'nope'"), std::string::npos) << msg;
  msg = errorOf([&] { f.stringAttribute("/nowhere", "unit"); });
  EXPECT_NE(msg.find("'/nowhere'"), std::string::npos) << msg;
  msg = errorOf([&] { f.readDoubles("/"); });
  EXPECT_NE(msg.find("not a dataset"), std::string::npos) << msg;
}

TEST(Errors, WrongTypesAndShapes) {
  const std::string path = fileFor("types");
  Hdf5File f(path, Hdf5File::Mode::Create);
  f.writeDoubles("/d", {2}, ramp(2, 1.0).data());
  f.writeString("/s", "text");
  f.setAttribute("/", "x", 1.5);
  f.setAttribute("/", "s", "text");
  std::string msg = errorOf([&] { f.readInts("/d"); });
  EXPECT_NE(msg.find("readDoubles"), std::string::npos) << msg;
  msg = errorOf([&] { f.readDoubles("/s"); });
  EXPECT_NE(msg.find("readString"), std::string::npos) << msg;
  msg = errorOf([&] { f.readString("/d"); });
  EXPECT_NE(msg.find("not a string"), std::string::npos) << msg;
  msg = errorOf([&] { f.intAttribute("/", "x"); });
  EXPECT_NE(msg.find("doubleAttribute"), std::string::npos) << msg;
  msg = errorOf([&] { f.doubleAttribute("/", "s"); });
  EXPECT_NE(msg.find("stringAttribute"), std::string::npos) << msg;
  msg = errorOf([&] { f.writeDoubles("/d/child", {1}, ramp(1, 1.0).data()); });
  EXPECT_NE(msg.find("'/d' is a dataset"), std::string::npos) << msg;
  msg = errorOf([&] { f.writeDoubles("/bad", {}, nullptr); });
  EXPECT_NE(msg.find("rank 0"), std::string::npos) << msg;
  msg = errorOf([&] { f.writeDoubles("/bad", {3}, nullptr); });
  EXPECT_NE(msg.find("null data"), std::string::npos) << msg;
  f.setAttribute("/g", "a", 1LL);
  msg = errorOf([&] { f.writeDoubles("/g", {1}, ramp(1, 1.0).data()); });
  EXPECT_NE(msg.find("is a group"), std::string::npos) << msg;
  Series s(f, "/series", {3}, 10);
  msg = errorOf([&] { s.append(std::vector<double>{1.0, 2.0}); });
  EXPECT_NE(msg.find("expected 3"), std::string::npos) << msg;
  msg = errorOf([&] { f.writeDoubles("/series", {1}, ramp(1, 1.0).data()); });
  EXPECT_NE(msg.find("Series is writing"), std::string::npos) << msg;
  msg = errorOf([&] { Series z(f, "/zero", {0}); });
  EXPECT_NE(msg.find("zero dimension"), std::string::npos) << msg;
  msg = errorOf([&] { Series z(f, "/nobuffer", {}, 0); });
  EXPECT_NE(msg.find("bufferRecords"), std::string::npos) << msg;
  msg = errorOf([&] { f.exists(""); });
  EXPECT_NE(msg.find("empty object path"), std::string::npos) << msg;
}

TEST(Errors, WritingAReadOnlyFile) {
  const std::string path = fileFor("readonly");
  { Hdf5File f(path, Hdf5File::Mode::Create); }
  Hdf5File f(path, Hdf5File::Mode::ReadOnly);
  std::string msg = errorOf([&] { f.writeInts("/x", {1LL}); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("ReadWrite"), std::string::npos) << msg;
  msg = errorOf([&] { f.setAttribute("/", "a", 1.0); });
  EXPECT_NE(msg.find("ReadOnly"), std::string::npos) << msg;
  msg = errorOf([&] { Series s(f, "/t", {}); });
  EXPECT_NE(msg.find("ReadOnly"), std::string::npos) << msg;
}

TEST(Errors, UseAfterClose) {
  const std::string path = fileFor("closed");
  Hdf5File f(path, Hdf5File::Mode::Create);
  f.close();
  EXPECT_FALSE(f.isOpen());
  const std::string msg = errorOf([&] { f.exists("/"); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("closed"), std::string::npos) << msg;
}
