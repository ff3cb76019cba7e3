// The generic .npy / zip / .npz layer: round trips, numpy interoperability both ways, and corrupt
// or hostile archives.
#include "formats/reference/npz_file.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "formats/reference/zip_archive.hpp"
#include "reference_test_util.hpp"
#include "retarget/core/file_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

using npz::Array;
using npz::DType;
using npz::NamedArray;

std::vector<NamedArray> sample_arrays() {
  std::vector<NamedArray> a;
  a.push_back({"f8", Array::from_doubles({2, 3}, {0.1, -2.5, 1e-300, 3.0, -0.0, 1e300}), 0});
  a.push_back({"f4", Array::from_doubles({3}, {1.5, -0.25, 3.0}, DType::Float32), 0});
  a.push_back({"i8", Array::from_ints({2}, {-(std::int64_t{1} << 40), std::int64_t{1} << 40}), 0});
  a.push_back({"i4", Array::from_ints({2, 2}, {-7, 0, 7, 2147483647}, DType::Int32), 0});
  a.push_back({"u1", Array::from_ints({3}, {0, 128, 255}, DType::UInt8), 0});
  a.push_back({"b1", Array::from_ints({2, 2}, {1, 0, 0, 1}, DType::Bool), 0});
  a.push_back({"names", Array::from_strings({3}, {"left_hip", "", "gelenk_\xc3\xa4"}), 0});
  a.push_back({"scalar", Array::from_doubles({}, {42.0}), 0});
  a.push_back({"empty", Array::from_doubles({0, 3}, {}), 0});
  a.push_back({"cube", Array::from_doubles({2, 2, 2}, {0, 1, 2, 3, 4, 5, 6, 7}), 0});
  return a;
}

void expect_same(const std::vector<NamedArray>& a, const npz::NpzFile& f) {
  ASSERT_EQ(f.arrays.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(a[i].key);
    EXPECT_EQ(f.arrays[i].key, a[i].key);
    EXPECT_EQ(f.arrays[i].array.descr(), a[i].array.descr());
    EXPECT_EQ(f.arrays[i].array.shape, a[i].array.shape);
    EXPECT_EQ(f.arrays[i].array.data, a[i].array.data);
  }
}

TEST(Npy, HeaderIsNumpysFormat10AlignedTo64) {
  const std::string npy = npz::encode_npy(Array::from_doubles({2, 3}, {1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header_len = static_cast<unsigned char>(npy[8]) | (static_cast<unsigned char>(npy[9]) << 8);
  EXPECT_EQ((10 + header_len) % 64, 0u);
  EXPECT_EQ(npy.substr(10, 60).find("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }"), 0u);
  EXPECT_EQ(npy[10 + header_len - 1], '\n');
  EXPECT_EQ(npy.size(), 10 + header_len + 48);
  EXPECT_NE(npz::encode_npy(Array::from_doubles({3}, {1, 2, 3})).find("'shape': (3,), }"), std::string::npos);
  EXPECT_NE(npz::encode_npy(Array::from_doubles({}, {1})).find("'shape': (), }"), std::string::npos);
}

TEST(Npy, ValuesAndStrings) {
  const auto a = sample_arrays();
  EXPECT_EQ(a[0].array.to_doubles(), (std::vector<double>{0.1, -2.5, 1e-300, 3.0, -0.0, 1e300}));
  EXPECT_EQ(a[1].array.to_doubles(), (std::vector<double>{1.5, -0.25, 3.0}));
  EXPECT_EQ(a[2].array.number(0), -1099511627776.0);
  EXPECT_EQ(a[3].array.number(3), 2147483647.0);
  EXPECT_EQ(a[4].array.number(2), 255.0);
  EXPECT_EQ(a[6].array.descr(), "<U8");
  EXPECT_EQ(a[6].array.to_strings(), (std::vector<std::string>{"left_hip", "", "gelenk_\xc3\xa4"}));
  EXPECT_THROW(Array::from_strings({1}, {"bad \xff utf8"}), InputError);
}

TEST(Npy, DecodesFortranOrderAndVersion2) {
  // 2 x 3 array stored column-major: memory 1 4 2 5 3 6 means rows [1 2 3], [4 5 6].
  const Array c = Array::from_doubles({6}, {1, 4, 2, 5, 3, 6});
  std::string header = "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }";
  header.append(128 - 12 - header.size() - 1, ' ');
  header.push_back('\n');
  std::string npy = std::string("\x93NUMPY\x02\x00", 8);
  const std::uint32_t len = static_cast<std::uint32_t>(header.size());
  npy.append(reinterpret_cast<const char*>(&len), 4);  // little-endian host (x86/arm64)
  npy += header + c.data;
  const Array a = npz::decode_npy(npy, "t.npy");
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(a.to_doubles(), (std::vector<double>{1, 2, 3, 4, 5, 6}));
}

TEST(Npy, BadHeadersAreErrors) {
  auto npy_with = [](const std::string& dict, const std::string& data) {
    std::string h = dict + "\n";
    std::string s = std::string("\x93NUMPY\x01\x00", 8);
    s.push_back(static_cast<char>(h.size()));
    s.push_back(0);
    return s + h + data;
  };
  auto decode = [](const std::string& bytes) { return [bytes] { npz::decode_npy(bytes, "x.npz@0x0 [a.npy]"); }; };
  test::expect_input_error(decode("\x93NUMP"), {"x.npz@0x0 [a.npy]", "magic"});
  test::expect_input_error(decode(npy_with("{'descr': '>f8', 'fortran_order': False, 'shape': (1,), }", std::string(8, 0))),
                           {"unsupported dtype '>f8'"});
  test::expect_input_error(decode(npy_with("{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }", std::string(8, 0))),
                           {"has 8 bytes", "need 16 bytes"});
  test::expect_input_error(
      decode(npy_with("{'descr': '<f8', 'fortran_order': False, 'shape': (100000000000, 100000000000), }", std::string(8, 0))),
      {"more than the file holds"});
  test::expect_input_error(decode(npy_with("{'descr': '<f8', 'shape': (1,), }", std::string(8, 0))), {"lacks one of"});
  test::expect_input_error(decode(npy_with("{'descr': '<f8', 'fortran_order': Maybe, 'shape': (1,), }", "")), {"True or False"});
  test::expect_input_error(decode(npy_with("{'descr': '<U2', 'fortran_order': False, 'shape': (1,), }", std::string("\x00\xD8\x00\x00\x41\x00\x00\x00", 8))),
                           {"invalid unicode code point 0xd800"});
  std::string long_header = std::string("\x93NUMPY\x01\x00\xff\xff", 10) + "{";
  test::expect_input_error(decode(long_header), {"runs past"});
}

TEST(Npz, RoundTripStoredAndDeflated) {
  const auto a = sample_arrays();
  for (bool compress : {false, true}) {
    npz::NpzWriteOptions o;
    o.compress = compress;
    const std::string bytes = npz::encode_npz(a, o);
    expect_same(a, npz::decode_npz(bytes, "s.npz"));
    EXPECT_EQ(npz::encode_npz(a, o), bytes);  // deterministic
  }
  // Deflate pays off on real-sized arrays.
  std::vector<double> zeros(10000, 0.25);
  const std::vector<NamedArray> big = {{"z", Array::from_doubles({zeros.size()}, zeros), 0}};
  npz::NpzWriteOptions stored;
  stored.compress = false;
  EXPECT_LT(npz::encode_npz(big).size() * 20, npz::encode_npz(big, stored).size());
}

TEST(Npz, ReadsNumpysOwnFileFixture) {
  // Written by numpy 1.24's savez_compressed (tests/data/reference/make_numpy_fixture.py): zip64
  // extras in the local headers, a Fortran-ordered array, every supported dtype.
  const npz::NpzFile f = npz::read_npz(test::source_path("tests/data/reference/numpy_fixture.npz"));
  ASSERT_NE(f.find("joint_pos"), nullptr);
  const Array& q = *f.find("joint_pos");
  EXPECT_EQ(q.shape, (std::vector<std::size_t>{5, 3}));
  for (std::size_t t = 0; t < 5; ++t)
    for (std::size_t j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(q.number(t * 3 + j), 0.1 * static_cast<double>(t) + static_cast<double>(j));
  EXPECT_EQ(f.find("joint_names")->to_strings(), (std::vector<std::string>{"hip", "knee", "ankle_\xc3\xa4"}));
  EXPECT_EQ(f.find("contacts")->descr(), "|b1");
  EXPECT_EQ(f.find("contacts")->to_doubles(), (std::vector<double>{1, 1, 1, 0, 1, 0, 0, 1, 1, 1}));
  EXPECT_EQ(f.find("counts")->to_doubles(), (std::vector<double>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(f.find("big")->to_doubles(), (std::vector<double>{-1099511627776.0, 1099511627776.0}));
  EXPECT_EQ(f.find("small")->to_doubles(), (std::vector<double>{1.5, -2.25}));
  EXPECT_EQ(f.find("bytes_")->to_doubles(), (std::vector<double>{0, 255}));
  EXPECT_TRUE(f.find("scalar")->shape.empty());
  EXPECT_EQ(f.find("scalar")->number(0), 3.5);
}

TEST(Npz, NumpyLoadsOurFilesAndWeLoadNumpys) {
  if (!test::have_numpy()) GTEST_SKIP() << "/usr/bin/python3 with numpy not available";
  const std::string dir = test::scratch_dir();
  npz::write_npz(dir + "/ours.npz", sample_arrays());
  npz::NpzWriteOptions stored;
  stored.compress = false;
  npz::write_npz(dir + "/ours_stored.npz", sample_arrays(), stored);
  const std::string script = R"PY(
import sys, numpy as np
for path in sys.argv[1:3]:
    d = np.load(path)
    assert d["f8"].dtype == np.float64 and d["f8"].shape == (2, 3), d["f8"]
    assert d["f8"][0, 0] == 0.1 and d["f8"][1, 2] == 1e300 and np.signbit(d["f8"][1, 1])
    assert d["f4"].dtype == np.float32 and list(d["f4"]) == [1.5, -0.25, 3.0]
    assert d["i8"].dtype == np.int64 and list(d["i8"]) == [-(1 << 40), 1 << 40]
    assert d["i4"].dtype == np.int32 and d["i4"][1, 1] == 2147483647
    assert d["u1"].dtype == np.uint8 and list(d["u1"]) == [0, 128, 255]
    assert d["b1"].dtype == np.bool_ and d["b1"].tolist() == [[True, False], [False, True]]
    assert d["names"].dtype == np.dtype("<U8") and d["names"].tolist() == ["left_hip", "", "gelenk_\u00e4"]
    assert d["scalar"].shape == () and d["scalar"] == 42.0
    assert d["empty"].shape == (0, 3)
    assert d["cube"][1, 0, 1] == 5.0
# numpy's own files for the C++ side to read: stored and deflated, C and Fortran order
a = np.arange(12.0).reshape(3, 4) / 8
np.savez(sys.argv[3], a=a, f=np.asfortranarray(a), s=np.array(["x", "yz"]), b=np.array([True, False]))
np.savez_compressed(sys.argv[4], a=a, f=np.asfortranarray(a), s=np.array(["x", "yz"]), b=np.array([True, False]))
print("ok")
)PY";
  std::string out;
  const int rc = test::run_python(dir, script,
                                  dir + "/ours.npz " + dir + "/ours_stored.npz " + dir + "/np.npz " + dir + "/npc.npz", out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_EQ(out, "ok\n");
  for (const char* name : {"/np.npz", "/npc.npz"}) {
    const npz::NpzFile f = npz::read_npz(dir + name);
    std::vector<double> expect(12);
    for (int i = 0; i < 12; ++i) expect[static_cast<std::size_t>(i)] = i / 8.0;
    EXPECT_EQ(f.find("a")->to_doubles(), expect);
    EXPECT_EQ(f.find("f")->to_doubles(), expect);
    EXPECT_EQ(f.find("f")->shape, (std::vector<std::size_t>{3, 4}));
    EXPECT_EQ(f.find("s")->to_strings(), (std::vector<std::string>{"x", "yz"}));
    EXPECT_EQ(f.find("b")->to_doubles(), (std::vector<double>{1, 0}));
  }
}

// Offsets into an archive we wrote ourselves (no extras, no comment).
struct Layout {
  std::size_t end_record;
  std::size_t central;
};
Layout layout_of(const std::string& zip) {
  const std::size_t end = zip.size() - 22;
  std::uint32_t cd = 0;
  std::memcpy(&cd, zip.data() + end + 16, 4);
  return {end, cd};
}
void put32(std::string& s, std::size_t at, std::uint32_t v) { std::memcpy(&s[at], &v, 4); }
void put16(std::string& s, std::size_t at, std::uint16_t v) { std::memcpy(&s[at], &v, 2); }

TEST(Npz, CorruptArchivesAreOneLineErrorsWithOffsets) {
  const std::vector<NamedArray> one = {{"joint_pos", Array::from_doubles({4}, {1, 2, 3, 4}), 0}};
  npz::NpzWriteOptions stored;
  stored.compress = false;
  const std::string good = npz::encode_npz(one, stored);
  const std::string deflated = npz::encode_npz({{"z", Array::from_doubles({1000}, std::vector<double>(1000, 1.0)), 0}});
  const Layout L = layout_of(good);
  auto decode = [](const std::string& bytes) { return [bytes] { npz::decode_npz(bytes, "bad.npz"); }; };

  test::expect_input_error(decode(""), {"bad.npz@0x0", "not a zip"});
  test::expect_input_error(decode("hello, this is not a zip archive at all"), {"bad.npz@0x0", "no 'PK'"});
  // Truncations: anywhere before the end record loses it.
  for (std::size_t cut : {std::size_t{30}, good.size() / 2, good.size() - 1})
    test::expect_input_error(decode(good.substr(0, cut)), {"bad.npz@0x", "end of central directory not found"});
  // Bad CRC: flip a data byte of the stored entry.
  {
    std::string b = good;
    b[30 + 13 + 128 + 3] ^= 0x40;
    test::expect_input_error(decode(b), {"bad.npz@0x0 [joint_pos.npy]", "CRC mismatch"});
  }
  // Absurd sizes: uncompressed size far beyond what the compressed bytes could give.
  {
    std::string b = deflated;
    const Layout D = layout_of(b);
    put32(b, D.central + 24, 0xFFFFFFF0u);
    test::expect_input_error(decode(b), {"bad.npz@0x", "[z.npy]", "impossible"});
  }
  // Stored entry whose sizes disagree.
  {
    std::string b = good;
    put32(b, L.central + 24, 9999);
    test::expect_input_error(decode(b), {"[joint_pos.npy]", "stored entry"});
  }
  // Compressed size running past the data area.
  {
    std::string b = good;
    put32(b, L.central + 20, 0x7FFFFFF0u);
    put32(b, L.central + 24, 0x7FFFFFF0u);
    test::expect_input_error(decode(b), {"bad.npz@0x0 [joint_pos.npy]", "runs past the data area"});
  }
  // Local header offset outside the file.
  {
    std::string b = good;
    put32(b, L.central + 42, 0x10000000u);
    test::expect_input_error(decode(b), {"[joint_pos.npy]", "local header offset 0x10000000"});
  }
  // Central directory offset/size beyond the end record, and an absurd entry count.
  {
    std::string b = good;
    put32(b, L.end_record + 16, 0x00FFFFFFu);
    test::expect_input_error(decode(b), {"bad.npz@0x", "central directory"});
    b = good;
    put16(b, L.end_record + 10, 5000);
    put16(b, L.end_record + 8, 5000);
    test::expect_input_error(decode(b), {"5000 entries cannot fit"});
  }
  // Corrupt deflate stream; truncated deflate stream (sizes kept consistent).
  {
    std::string b = deflated;
    for (std::size_t i = 30 + 5; i < 30 + 15; ++i) b[i] = static_cast<char>(0xFF);
    test::expect_input_error(decode(b), {"bad.npz@0x0 [z.npy]"});
  }
  // Unsupported features.
  {
    std::string b = good;
    put16(b, L.central + 10, 14);  // LZMA
    test::expect_input_error(decode(b), {"compression method 14"});
    b = good;
    put16(b, L.central + 8, 1);
    test::expect_input_error(decode(b), {"encrypted"});
  }
  // Entries that are not arrays, and duplicates.
  {
    const std::string z = zip::write_archive({{"readme.txt", "hi", 0}}, zip::Method::Stored);
    test::expect_input_error(decode(z), {"bad.npz@0x0 [readme.txt]", "not a '<key>.npy'"});
    const std::string dup = zip::write_archive({{"a.npy", good, 0}, {"a.npy", good, 0}}, zip::Method::Stored);
    test::expect_input_error(decode(dup), {"[a.npy]", "duplicate"});
    const std::string garbage = zip::write_archive({{"a.npy", "not an npy", 0}}, zip::Method::Deflate);
    test::expect_input_error(decode(garbage), {"bad.npz@0x0 [a.npy]", "magic"});
  }
  // A decompression bomb is refused by the total-size limit before it is inflated.
  {
    npz::NpzReadOptions o;
    o.max_total_bytes = 4000;
    test::expect_input_error([&] { npz::decode_npz(deflated, "bomb.npz", o); }, {"bomb.npz@0x", "exceeds the 4000-byte limit"});
  }
}

}  // namespace
}  // namespace rt
