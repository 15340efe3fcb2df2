// Stage "volume", its files (volume.hpp, docs/formats.md "Field files"): every form read from
// bytes written here by hand, every writer read back bit for bit, and the damage each reader
// must refuse, with the line or byte offset and the problem named. volume_test.cpp holds the
// first tests and the fit of the real CT; these cover the contract form by form.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io/volume.hpp>
#include <vector>

#include "test_util.hpp"

using namespace tpmsfill;
using namespace tpmsfill::test;

namespace {

// Values as stored: little- or big-endian bytes of any arithmetic type.
template <class T>
std::string bytes_of(const std::vector<T>& values, bool big = false) {
  std::string out;
  for (const T v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
  }
  return out;
}

std::string zlib(const std::string& s) {
  uLongf size = compressBound(s.size());
  std::string out(size, '\0');
  compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(s.data()),
            s.size(), 9);
  out.resize(size);
  return out;
}

// What a ParseError said: its line or byte, and its reason.
struct Refusal {
  std::string where;   // "line N", "byte N", or what else happened
  std::string reason;  // ParseError::reason()
};

Refusal refusal(const std::string& bytes, const std::string& name) {
  try {
    parse_volume(bytes, name);
  } catch (const ParseError& e) {
    if (e.line()) return {"line " + std::to_string(*e.line()), e.reason()};
    return {"byte " + std::to_string(e.byte_offset().value_or(0)), e.reason()};
  } catch (const Error& e) {
    return {std::string("not a ParseError: ") + e.what(), ""};
  }
  return {"read", ""};
}

#define EXPECT_REFUSED(bytes, name, at, words)               \
  do {                                                       \
    const Refusal r_ = refusal(bytes, name);                 \
    EXPECT_EQ(r_.where, at) << r_.reason;                    \
    EXPECT_NE(r_.reason.find(words), std::string::npos)      \
        << "'" << r_.reason << "' does not say " << (words); \
  } while (false)

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Values that float32 cannot hold, the extremes of double, a subnormal, -0.
ScalarVolume awkward_volume(FieldSign sign) {
  ScalarVolume v;
  v.dims = {4, 3, 2};
  for (int n = 0; n < 24; ++n) v.values.push_back(std::sin(n * 1.3) * std::pow(10.0, n % 9 - 4));
  v.values[0] = -0.0;
  v.values[1] = std::numeric_limits<double>::denorm_min();
  v.values[2] = std::numeric_limits<double>::max();
  v.values[3] = -std::numeric_limits<double>::max();
  v.values[4] = 0.1;
  v.spacing = {0.1, 1.0 / 3.0, 2.5};
  v.origin = {0.05, 1.0 / 6.0, 1.25};
  v.sign = sign;
  return v;
}

// An INR header of `fields` padded to 256 bytes.
std::string inr_header(const std::string& fields) {
  std::string h = "#INRIMAGE-4#{\n" + fields;
  h.resize(252, '\n');
  return h + "##}\n";
}

const std::string kNrrd3 = "NRRD0005\ndimension: 3\n";

}  // namespace

// ---- writers and round trips ----------------------------------------------------------------

TEST(VolumeIo, EveryWriterReadsBackBitForBitWhenExact) {
  const auto dir = scratch_dir();
  for (const FieldSign sign : {FieldSign::Unknown, FieldSign::Signed, FieldSign::Unsigned}) {
    const ScalarVolume v = awkward_volume(sign);
    for (const char* name : {"a.tdf", "a.tdfb", "a.nrrd"}) {
      write_volume(dir / name, v, VolumeFormat::Auto, true);
      const VolumeFile back = read_volume_file(dir / name);
      EXPECT_EQ(back.format, volume_format_from_extension(name));
      EXPECT_EQ(back.volume.dims, v.dims) << name;
      EXPECT_TRUE(same_bits(back.volume.values, v.values)) << name;
      EXPECT_TRUE(std::signbit(back.volume.values[0])) << name << ": -0 kept";
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(back.volume.spacing[a], v.spacing[a], 1e-15) << name;
        EXPECT_NEAR(back.volume.origin[a], v.origin[a], 1e-15) << name;
      }
      EXPECT_EQ(back.volume.sign, sign) << name;
      EXPECT_TRUE(back.warnings.empty()) << name;
    }
  }
}

// A field that sits away from the seed's box at the origin (from a CT whose first centre is at
// (0, 0, 0), or a mesh at 150 mm) keeps its place in every form: the seed's forms used to move
// it by half a cell, or to the origin.
TEST(VolumeIo, PlacedFieldsKeepTheirPlace) {
  const auto dir = scratch_dir();
  for (const Vec3 origin : {Vec3{0, 0, 0}, Vec3{150.25, -80.125, 1000.5}}) {
    ScalarVolume v = awkward_volume(FieldSign::Signed);
    v.origin = origin;
    for (const char* name : {"p.tdf", "p.tdfb", "p.nrrd"}) {
      write_volume(dir / name, v, VolumeFormat::Auto, true);
      const VolumeFile back = read_volume_file(dir / name);
      EXPECT_EQ(back.volume.origin, origin) << name;
      EXPECT_TRUE(same_bits(back.volume.values, v.values)) << name;
    }
    EXPECT_EQ(read_file(dir / "p.tdfb")[4], 2) << "an origin needs version 2";
  }
  // At the seed's own place nothing is added: version 1, no origin line, as before.
  const ScalarVolume seed = awkward_volume(FieldSign::Signed);
  write_volume(dir / "s.tdfb", seed);
  write_volume(dir / "s.tdf", seed);
  EXPECT_EQ(read_file(dir / "s.tdfb")[4], 1);
  EXPECT_EQ(read_file(dir / "s.tdf").find("origin"), std::string::npos);
  // An origin without a size has nothing to place.
  EXPECT_THROW(parse_volume("tpmsfill-field 1\norigin 1 2 3\n1 1 1\n0.5\n", "o.tdf"), ParseError);
}

TEST(VolumeIo, TheUnitCubeStaysUnitless) {
  ScalarVolume v;
  v.dims = {2, 1, 1};
  v.values = {-1.5, 2.25};
  const auto dir = scratch_dir();
  for (const char* name : {"u.tdf", "u.tdfb", "u.nrrd"}) {
    write_volume(dir / name, v);
    const VolumeFile back = read_volume_file(dir / name);
    EXPECT_FALSE(back.volume.has_physical_size()) << name;
    EXPECT_EQ(back.volume.spacing, (std::array<double, 3>{})) << name;
    EXPECT_EQ(back.volume.origin, Vec3{}) << name;
    EXPECT_EQ(back.volume.values, v.values) << name;
  }
  EXPECT_EQ(read_file(dir / "u.tdf").find("size"), std::string::npos);
}

TEST(VolumeIo, WithoutExactValuesAreStoredAsFloat32) {
  const ScalarVolume v = awkward_volume(FieldSign::Signed);
  ScalarVolume small = v;
  small.values[2] = small.values[3] = 1;  // double's extremes overflow float
  const auto dir = scratch_dir();
  write_volume(dir / "f.tdfb", small);
  write_volume(dir / "f.nrrd", small);
  write_volume(dir / "f.tdf", small);
  EXPECT_EQ(std::filesystem::file_size(dir / "f.tdfb"), 44u + 4 * 24);
  EXPECT_NE(read_file(dir / "f.nrrd").find("type: float\n"), std::string::npos);
  for (const char* name : {"f.tdfb", "f.nrrd", "f.tdf"}) {
    const VolumeFile back = read_volume_file(dir / name);
    for (std::size_t n = 0; n < small.values.size(); ++n)
      EXPECT_EQ(back.volume.values[n], double(float(small.values[n]))) << name << " value " << n;
  }
  EXPECT_EQ(read_volume_file(dir / "f.tdfb").element_type, "float32");
  write_volume(dir / "d.tdfb", v, VolumeFormat::Auto, true);
  EXPECT_EQ(std::filesystem::file_size(dir / "d.tdfb"), 44u + 8 * 24);
  EXPECT_EQ(read_volume_file(dir / "d.tdfb").element_type, "float64");
}

TEST(VolumeIo, TheBinaryFormIsLaidOutAsDocumented) {
  ScalarVolume v;
  v.dims = {2, 1, 3};
  v.values = {0, 1, 2, 3, 4, 5};
  v.spacing = {0.5, 2, 1};
  v.origin = {0.25, 1, 0.5};
  v.sign = FieldSign::Unsigned;
  const auto dir = scratch_dir();
  write_volume(dir / "b.tdfb", v, VolumeFormat::FieldBinary, true);
  const std::string b = read_file(dir / "b.tdfb");
  ASSERT_EQ(b.size(), 44u + 6 * 8);
  EXPECT_EQ(b.substr(0, 4), "TDFB");
  EXPECT_EQ(b.substr(4, 4), std::string("\x01\x00\x01\x02", 4));  // version, float64, unsigned
  EXPECT_EQ(b.substr(8, 12), bytes_of<std::uint32_t>({2, 1, 3}));
  EXPECT_EQ(b.substr(20, 24), bytes_of<double>({1, 2, 3}));  // the box: spacing × counts
  EXPECT_EQ(b.substr(44), bytes_of<double>(v.values));
}

TEST(VolumeIo, WritingRefusesWhatItCannotWrite) {
  ScalarVolume v;
  v.dims = {1, 1, 2};
  v.values = {1, 2};
  const auto dir = scratch_dir();
  for (const char* name : {"a.mha", "a.mhd", "a.inr", "a.raw", "a"}) {
    try {
      write_volume(dir / name, v);
      ADD_FAILURE() << name << " was written";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(".tdf"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(".nrrd"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / name)) << name;
  }
  // Forced formats win over the extension.
  write_volume(dir / "x.dat", v, VolumeFormat::Nrrd);
  EXPECT_EQ(parse_volume(read_file(dir / "x.dat"), "x.dat").format, VolumeFormat::Nrrd);

  ScalarVolume bad = v;
  bad.values.push_back(3);
  EXPECT_THROW(write_volume(dir / "c.tdf", bad), InputError);
  bad = v;
  bad.values[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_volume(dir / "n.tdf", bad), InputError);
  bad = v;
  bad.spacing = {1, 0, 1};
  EXPECT_THROW(write_volume(dir / "s.tdf", bad), InputError);
  bad = v;
  bad.dims = {0, 1, 2};
  EXPECT_THROW(require_valid(bad), InputError);
  bad = v;
  bad.spacing = {1, -1, 1};
  EXPECT_THROW(require_valid(bad), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "c.tdf"));
  EXPECT_NO_THROW(require_valid(v));
}

// ---- the seed's text form ---------------------------------------------------------------------

TEST(VolumeIo, TextFormHeaderLines) {
  const VolumeFile f = parse_volume(
      "tpmsfill-field 1   # magic\n# comment\nsize 4 2 9\nsign unsigned\n4 2 3 0 1\r\n"
      "2 3 4 5 6 7\n 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23\n\n",
      "h.txt");  // detected by its magic, not its extension
  EXPECT_EQ(f.format, VolumeFormat::FieldText);
  EXPECT_EQ(f.volume.dims, (std::array<int, 3>{4, 2, 3}));
  ASSERT_EQ(f.volume.values.size(), 24u);
  EXPECT_EQ(f.volume.values[1], 1);  // values may follow the counts on their line
  EXPECT_EQ(f.volume.at(3, 1, 2), 23);
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{1, 1, 3}));  // size / counts
  EXPECT_EQ(f.volume.origin, (Vec3{0.5, 0.5, 1.5}));              // half a cell
  EXPECT_EQ(f.volume.sign, FieldSign::Unsigned);
  EXPECT_FALSE(f.compressed);
  // Without the magic, the extension names the form; gzip is unwrapped first.
  const VolumeFile g = parse_volume(gzip("1 1 2\n+1.5e0 -2\n"), "g.tdf.gz");
  EXPECT_TRUE(g.compressed);
  EXPECT_EQ(g.volume.values, (std::vector<double>{1.5, -2}));
  EXPECT_EQ(g.volume.sign, FieldSign::Unknown);
}

TEST(VolumeIo, TextFormDamageNamesItsLine) {
  EXPECT_REFUSED("2 1 3\n1 2\n3 4\n5\n", "few.tdf", "line 4", "5 of 6 values");
  EXPECT_REFUSED("2 1 1\n1 2\n\n3 # too many\n", "many.tdf", "line 4", "more values than the 2");
  EXPECT_REFUSED("2 1 1 1 2 3\n", "many1.tdf", "line 1", "more values than the 2");
  EXPECT_REFUSED("1 1 1 nan\n", "nan1.tdf", "line 1", "not a finite number");
  EXPECT_REFUSED("1 1 2\n1\n-inf\n", "inf.tdf", "line 3", "not a finite number");
  EXPECT_REFUSED("1 1 1\n1e999\n", "huge.tdf", "line 2", "out of range");
  EXPECT_REFUSED("1 1 1\n0x10\n", "hex.tdf", "line 2", "'0x10' is not a number");
  EXPECT_REFUSED("1 1 1\n1,5\n", "comma.tdf", "line 2", "'1,5' is not a number");
  EXPECT_REFUSED("tpmsfill-field 2\n1 1 1\n0\n", "v2.tdf", "line 1", "version 1");
  EXPECT_REFUSED("\nsign maybe\n1 1 1\n0\n", "sign.tdf", "line 2", "maybe");
  EXPECT_REFUSED("size 1 1\n1 1 1\n0\n", "size.tdf", "line 1", "three lengths");
  EXPECT_REFUSED("size 1 -1 1\n1 1 1\n0\n", "neg.tdf", "line 1", "positive length");
  EXPECT_REFUSED("1 1\n0\n", "counts.tdf", "line 1", "counts 'w h d'");
  EXPECT_REFUSED("0 1 1\n", "zero.tdf", "line 1", "not a dimension");
  EXPECT_REFUSED("1 1 2.5\n0 0\n", "frac.tdf", "line 1", "not a dimension");
  EXPECT_REFUSED("# only a comment\n", "none.tdf", "line 1", "no counts");
  // Declared counts the text cannot hold fail before anything is allocated, at once.
  const auto start = std::chrono::steady_clock::now();
  EXPECT_REFUSED("100000 100000 100000\n1 2 3\n", "big.tdf", "line 1", "more than the file holds");
  EXPECT_REFUSED("1048576 1048576 1048576 1 2 3\n", "big2.tdf", "line 1",
                 "more than the file holds");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

// ---- the seed's binary form -------------------------------------------------------------------

namespace {

std::string tdfb(std::uint8_t type, std::uint8_t sign, std::array<std::uint32_t, 3> dims,
                 std::array<double, 3> size, const std::string& values) {
  std::string b = "TDFB" + bytes_of<std::uint16_t>({1});
  b += static_cast<char>(type);
  b += static_cast<char>(sign);
  b += bytes_of<std::uint32_t>({dims[0], dims[1], dims[2]});
  b += bytes_of<double>({size[0], size[1], size[2]});
  return b + values;
}

}  // namespace

TEST(VolumeIo, BinaryFormReadFromHandWrittenBytes) {
  VolumeFile f = parse_volume(tdfb(0, 1, {2, 1, 1}, {4, 1, 1}, bytes_of<float>({-1.5f, 2})), "x");
  EXPECT_EQ(f.format, VolumeFormat::FieldBinary);
  EXPECT_EQ(f.element_type, "float32");
  EXPECT_EQ(f.volume.values, (std::vector<double>{-1.5, 2}));
  EXPECT_EQ(f.volume.sign, FieldSign::Signed);
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{2, 1, 1}));
  EXPECT_EQ(f.volume.origin, (Vec3{1, 0.5, 0.5}));
  f = parse_volume(tdfb(1, 2, {1, 1, 2}, {0, 0, 0}, bytes_of<double>({0.1, 1e300})), "y");
  EXPECT_EQ(f.element_type, "float64");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0.1, 1e300}));
  EXPECT_EQ(f.volume.sign, FieldSign::Unsigned);
  EXPECT_FALSE(f.volume.has_physical_size());
}

TEST(VolumeIo, BinaryFormDamageNamesItsByte) {
  const std::string two = bytes_of<float>({1, 2});
  EXPECT_REFUSED(std::string("TDFB\x01\x00", 6), "h.tdfb", "byte 6", "header is cut short");
  EXPECT_REFUSED(tdfb(0, 0, {2, 1, 1}, {}, two).substr(0, 44 + 7), "t.tdfb", "byte 44",
                 "7 bytes of values where the counts need 8");
  EXPECT_REFUSED(tdfb(0, 0, {2, 1, 1}, {}, two + "x"), "l.tdfb", "byte 44",
                 "9 bytes of values where the counts need 8");
  EXPECT_REFUSED(tdfb(2, 0, {2, 1, 1}, {}, two), "ty.tdfb", "byte 6", "unknown value type 2");
  EXPECT_REFUSED(tdfb(0, 3, {2, 1, 1}, {}, two), "si.tdfb", "byte 7", "unknown sign 3");
  EXPECT_REFUSED(tdfb(0, 0, {2, 0, 1}, {}, two), "d.tdfb", "byte 12", "dimension 0");
  EXPECT_REFUSED(tdfb(0, 0, {2, 1, 1}, {1, 0, 1}, two), "s.tdfb", "byte 20", "all three axes");
  EXPECT_REFUSED(tdfb(0, 0, {2, 1, 1}, {1, -1, 1}, two), "n.tdfb", "byte 28", ">= 0");
  EXPECT_REFUSED(tdfb(0, 0, {2, 1, 1}, {}, bytes_of<float>({1, std::nanf("")})), "nan.tdfb",
                 "byte 48", "value 1 is not finite");
  EXPECT_REFUSED(tdfb(1, 0, {1, 1, 1}, {}, bytes_of<double>({HUGE_VAL})), "inf.tdfb", "byte 44",
                 "not finite");
  std::string v3 = tdfb(0, 0, {2, 1, 1}, {}, two);
  v3[4] = 3;
  EXPECT_REFUSED(v3, "v3.tdfb", "byte 4", "versions 1 and 2");
  // Version 2 holds an origin after the size: one without a size has nothing to place.
  std::string v2 = tdfb(0, 0, {2, 1, 1}, {}, std::string(24, '\0') + two);
  v2[4] = 2;
  EXPECT_REFUSED(v2, "v2.tdfb", "byte 44", "an origin needs a size");
  const auto start = std::chrono::steady_clock::now();
  EXPECT_REFUSED(tdfb(1, 0, {1u << 20, 1u << 20, 1u << 20}, {}, two), "big.tdfb", "byte 44",
                 "8 bytes of values where the counts need 9223372036854775808");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

// ---- NRRD ---------------------------------------------------------------------------------

TEST(VolumeIo, NrrdElementTypesAndEndianness) {
  VolumeFile f = parse_volume(kNrrd3 + "type: uchar\nsizes: 3 1 1\nencoding: raw\n\n" +
                                  bytes_of<std::uint8_t>({0, 127, 255}),
                              "u8.nrrd");
  EXPECT_EQ(f.element_type, "uint8");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0, 127, 255}));
  f = parse_volume(kNrrd3 + "type: signed char\nsizes: 2 1 1\n\n\x80\x7f", "i8.nrrd");
  EXPECT_EQ(f.volume.values, (std::vector<double>{-128, 127}));
  f = parse_volume(kNrrd3 + "type: short\nsizes: 1 3 1\nendian: big\nencoding: raw\n\n" +
                       bytes_of<std::int16_t>({-32768, -2, 300}, true),
                   "i16.nrrd");
  EXPECT_EQ(f.element_type, "int16");
  EXPECT_EQ(f.volume.values, (std::vector<double>{-32768, -2, 300}));
  f = parse_volume(kNrrd3 + "type: unsigned short int\nsizes: 1 1 2\nendian: little\n\n" +
                       bytes_of<std::uint16_t>({65535, 1}),
                   "u16.nrrd");
  EXPECT_EQ(f.volume.values, (std::vector<double>{65535, 1}));
  f = parse_volume(kNrrd3 + "type: int32\nsizes: 1 1 1\nendian: big\n\n" +
                       bytes_of<std::int32_t>({-123456789}, true),
                   "i32.nrrd");
  EXPECT_EQ(f.volume.values, (std::vector<double>{-123456789}));
  f = parse_volume(
      kNrrd3 + "type: float\nsizes: 2 1 1\nendian: big\n\n" + bytes_of<float>({0.5f, -3}, true),
      "f32.nrrd");
  EXPECT_EQ(f.element_type, "float32");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0.5, -3}));
  f = parse_volume(kNrrd3 + "type: double\nsizes: 2 1 1\n\n" + bytes_of<double>({0.1, -1e-300}),
                   "f64.nrrd");
  EXPECT_EQ(f.element_type, "float64");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0.1, -1e-300}));
  EXPECT_EQ(f.volume.sign, FieldSign::Unknown);
}

TEST(VolumeIo, NrrdGeometry) {
  const std::string data = bytes_of<std::uint8_t>({1, 2, 3, 4, 5, 6, 7, 8});
  VolumeFile f = parse_volume(kNrrd3 +
                                  "type: uint8\nsizes: 2 2 2\nspace: 3D-right-handed\n"
                                  "space directions: (0.5,0,0) (0, 0.25, 0) (0,0,2)\n"
                                  "space origin: (10, -20, 30.5)\nkinds: domain domain domain\n"
                                  "# comment\nunknown:=ignored: really\n\n" +
                                  data,
                              "geo.nrrd");
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{0.5, 0.25, 2}));
  EXPECT_EQ(f.volume.origin, (Vec3{10, -20, 30.5}));
  f = parse_volume(kNrrd3 + "type: uint8\nsizes: 2 2 2\nspacings: 1 2 3\n\n" + data, "sp.nrrd");
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(f.volume.origin, Vec3{});
  // An axis stored backwards (Slicer's LPS files) is turned round: same cells, same places.
  f = parse_volume(kNrrd3 +
                       "type: uint8\nsizes: 2 2 2\nspace directions: (-0.5,0,0) (0,1,0) (0,0,-2)\n"
                       "space origin: (10,0,4)\n\n" +
                       data,
                   "flip.nrrd");
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{0.5, 1, 2}));
  EXPECT_EQ(f.volume.origin, (Vec3{9.5, 0, 2}));
  EXPECT_EQ(f.volume.values, (std::vector<double>{6, 5, 8, 7, 2, 1, 4, 3}));
  // The stored cell (i, j, k) was at origin + (-0.5 i, j, -2 k); it still is.
  EXPECT_EQ(f.volume.at(1, 0, 1), 1);  // stored first, at (10, 0, 4)
}

TEST(VolumeIo, NrrdEncodingsAndSkips) {
  const std::string head = kNrrd3 + "type: int16\nsizes: 3 1 1\nendian: little\n";
  const std::string raw = bytes_of<std::int16_t>({-7, 0, 7});
  const std::vector<double> want{-7, 0, 7};
  EXPECT_EQ(parse_volume(head + "encoding: raw\n\n" + raw, "r.nrrd").volume.values, want);
  VolumeFile f = parse_volume(head + "encoding: gzip\n\n" + gzip(raw), "g.nrrd");
  EXPECT_TRUE(f.compressed);
  EXPECT_EQ(f.volume.values, want);
  EXPECT_EQ(parse_volume(head + "encoding: gz\n\n" + zlib(raw), "z.nrrd").volume.values, want);
  EXPECT_EQ(parse_volume(head + "encoding: ascii\n\n-7\n0 7\n", "a.nrrd").volume.values, want);
  EXPECT_EQ(parse_volume(head + "encoding: text\n\n -7 0\t7", "t.nrrd").volume.values, want);
  // line skip, then byte skip (on the decompressed data for gzip, as teem reads it).
  EXPECT_EQ(
      parse_volume(head + "line skip: 2\nbyte skip: 1\n\nP5\n3 1\n#" + raw, "s.nrrd").volume.values,
      want);
  EXPECT_EQ(parse_volume(head + "encoding: gzip\nbyte skip: 2\n\n" + gzip("xx" + raw), "sg.nrrd")
                .volume.values,
            want);
  EXPECT_EQ(
      parse_volume(head + "byte skip: -1\n\n" + "leading junk" + raw, "end.nrrd").volume.values,
      want);
  // A whole gzipped file is unwrapped before its header is read.
  f = parse_volume(gzip(head + "encoding: raw\n\n" + raw), "w.nrrd.gz");
  EXPECT_TRUE(f.compressed);
  EXPECT_EQ(f.volume.values, want);
}

TEST(VolumeIo, NrrdDetachedData) {
  const auto dir = scratch_dir();
  const std::string head = kNrrd3 + "type: float\nsizes: 2 1 1\n";
  write_file(dir / "v.raw", bytes_of<float>({1, 2}));
  write_file(dir / "v.nhdr", head + "encoding: raw\ndata file: v.raw\n");
  VolumeFile f = read_volume_file(dir / "v.nhdr");
  EXPECT_EQ(f.volume.values, (std::vector<double>{1, 2}));
  std::filesystem::create_directories(dir / "sub");
  write_file(dir / "sub" / "v.raw.gz", gzip(bytes_of<float>({3, 4})));
  write_file(dir / "h.nhdr", head + "encoding: gzip\ndatafile: sub/v.raw.gz\n");
  EXPECT_EQ(read_volume_file(dir / "h.nhdr").volume.values, (std::vector<double>{3, 4}));
  write_file(dir / "t.txt", "1\n2\nx\n");
  write_file(dir / "t.nhdr", head + "encoding: ascii\ndata file: t.txt\n");
  try {  // the error is in the data file, at its own line
    read_volume_file(dir / "t.nhdr");
    ADD_FAILURE() << "read";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.source(), (dir / "t.txt").string());
    EXPECT_EQ(e.line(), 3u);
  }
  // A missing data file is an IoError naming it; in memory, a detached header is refused.
  write_file(dir / "m.nhdr", head + "data file: gone.raw\n");
  try {
    read_volume_file(dir / "m.nhdr");
    ADD_FAILURE() << "read";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("gone.raw"), std::string::npos) << e.what();
  }
  EXPECT_REFUSED(head + "data file: v.raw\n", "v.nhdr", "line 5", "cannot be followed");
  write_file(dir / "l.nhdr", head + "data file: LIST\nv.raw\n");
  EXPECT_THROW(read_volume_file(dir / "l.nhdr"), ParseError);
}

// Issue 37: gzip bombs. An NRRD or MetaImage whose header declares 256 bytes of data and whose
// gzip holds 64 MiB of zeros is refused once the data passes 256 bytes, not after the whole
// inflation (1 GiB of zeros peaked at 2.1 GB and then read exit 0); detached data that is a
// FIFO is refused instead of waited on.
TEST(VolumeIo, CompressedDataStopsAtTheSizeItsHeaderDeclares) {
  const std::string zeros = gzip(std::string(std::size_t{64} << 20, '\0'));
  ASSERT_LT(zeros.size(), 1u << 20);
  const std::string nrrd = kNrrd3 + "type: uint8\nsizes: 16 4 4\nencoding: gzip\n\n" + zeros;
  const std::string mha =
      "ObjectType = Image\nNDims = 3\nDimSize = 16 4 4\nElementType = MET_UCHAR\n"
      "CompressedData = True\nElementDataFile = LOCAL\n" +
      zeros;
  // A gzipped binary form (TDFB) whose header declares 2 x 2 x 2 float32s: 44 + 32 bytes.
  std::string tdfb("TDFB\x01\x00\x00\x01", 8);
  for (const std::uint32_t d : {2u, 2u, 2u}) tdfb.append(reinterpret_cast<const char*>(&d), 4);
  tdfb.append(24, '\0');
  const std::string whole = gzip(tdfb + std::string(std::size_t{64} << 20, '\0'));
  try {
    parse_volume(whole, "bomb.tdfb.gz");
    ADD_FAILURE() << "bomb.tdfb.gz was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("more than 76 bytes, the size its header declares"),
              std::string::npos)
        << e.what();
  }
  for (const auto& [bytes, name] : {std::pair{nrrd, "bomb.nrrd"}, std::pair{mha, "bomb.mha"}}) {
    const auto start = std::chrono::steady_clock::now();
    try {
      parse_volume(bytes, name);
      ADD_FAILURE() << name << " was read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("more than 256 bytes, the size its header declares"),
                std::string::npos)
          << e.what();
    }
    // Stopped at the first inflated chunk: far below the 64 MiB's inflation.
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2)) << name;
  }
}

TEST(VolumeIo, DataFilesThatAreNotRegularFilesAreRefused) {
  const auto dir = scratch_dir();
  ASSERT_EQ(mkfifo((dir / "pipe.raw").c_str(), 0600), 0);
  write_file(dir / "f.nhdr", kNrrd3 + "type: float\nsizes: 2 1 1\ndata file: pipe.raw\n");
  try {
    read_volume_file(dir / "f.nhdr");
    ADD_FAILURE() << "read";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("it is a FIFO"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_volume_file(dir / "pipe.raw"), IoError);
}

TEST(VolumeIo, NrrdDamageNamesItsLineOrByte) {
  const std::string f8 = "type: float\nsizes: 2 1 1\n";
  const std::string two = bytes_of<float>({1, 2});
  EXPECT_REFUSED("NRRD0004\ntype: float\ndimension: 2\nsizes: 2 2\n\n" + two, "2d.nrrd", "line 3",
                 "not dimension 2");
  EXPECT_REFUSED("NRRD0004\ntype: float\ndimension: 4\nsizes: 1 2 1 1\n\n" + two, "4d.nrrd",
                 "line 3", "not dimension 4");
  EXPECT_REFUSED(kNrrd3 + "type: float\nsizes: 2 1\n\n" + two, "s.nrrd", "line 4", "gives 2 sizes");
  EXPECT_REFUSED(kNrrd3 + "type: block\nsizes: 2 1 1\n\n" + two, "t.nrrd", "line 3",
                 "unsupported NRRD type 'block'");
  EXPECT_REFUSED(kNrrd3 + "sizes: 2 1 1\n\n" + two, "nt.nrrd", "line 1", "no 'type'");
  EXPECT_REFUSED(kNrrd3 + f8 + "encoding: bzip2\n\n" + two, "e.nrrd", "line 5", "'bzip2'");
  EXPECT_REFUSED(kNrrd3 + f8 + "spacings\n\n" + two, "k.nrrd", "line 5", "key: value");
  EXPECT_REFUSED(kNrrd3 + f8 + "spacings: 1 nan 1\n\n" + two, "n.nrrd", "line 5", "'nan'");
  EXPECT_REFUSED(kNrrd3 + f8 + "space directions: (1,0,0) (0,1,0.5) (0,0,1)\n\n" + two, "r.nrrd",
                 "line 5", "rotated axes are not supported");
  EXPECT_REFUSED(kNrrd3 + f8 + "space origin: (1,2)\n\n" + two, "o.nrrd", "line 5",
                 "needs 3 numbers");
  EXPECT_REFUSED(kNrrd3 + f8 + "byte skip: 9\n\n" + two, "bs.nrrd", "line 5", "'byte skip' 9");
  EXPECT_REFUSED(kNrrd3 + f8 + "line skip: 2\n\n" + two, "ls.nrrd", "line 5", "the data has 0");
  EXPECT_REFUSED(kNrrd3 + f8 + "encoding: gzip\nbyte skip: -1\n\n" + two, "g1.nrrd", "line 6",
                 "only read with raw");
  // Data: cut short (named at its end), not finite (at its value), garbage gzip.
  const std::string head = kNrrd3 + f8 + "\n";
  EXPECT_REFUSED(head + two.substr(0, 5), "cut.nrrd", "byte " + std::to_string(head.size() + 5),
                 "5 of 8 bytes");
  EXPECT_REFUSED(head + bytes_of<float>({1, INFINITY}), "inf.nrrd",
                 "byte " + std::to_string(head.size() + 4), "value 1 is not finite");
  const std::string gz_head = kNrrd3 + f8 + "encoding: gzip\n\n";
  std::string broken = gzip(two);
  broken[12] = static_cast<char>(~broken[12]);
  const Refusal r = refusal(gz_head + broken, "gz.nrrd");
  EXPECT_EQ(r.where.rfind("byte ", 0), 0u) << r.where;
  EXPECT_GE(std::stoul(r.where.substr(5)), gz_head.size()) << "offset within the file";
  // ascii data: the line of the bad value.
  const std::string text = kNrrd3 + f8 + "encoding: ascii\n\n";
  EXPECT_REFUSED(text + "1\n\n2 3\n", "many.nrrd", "line 9", "more values than the 2");
  EXPECT_REFUSED(text + "1\nnan\n", "nan.nrrd", "line 8", "'nan' is not a finite number");
  EXPECT_REFUSED(text + "1\n", "few.nrrd", "line 7", "1 of 2 values");
  // Declared counts far beyond the bytes fail at once, before allocating.
  const auto start = std::chrono::steady_clock::now();
  const std::string huge = kNrrd3 + "type: double\nsizes: 100000 100000 100000\n";
  EXPECT_REFUSED(huge + "\n" + two, "h.nrrd", "byte " + std::to_string(huge.size() + 9),
                 "8 of 8000000000000000 bytes");
  EXPECT_REFUSED(huge + "encoding: ascii\n\n1 2 3\n", "ha.nrrd", "line 4", "values declared");
  EXPECT_REFUSED(huge + "encoding: gzip\n\n" + gzip(two), "hg.nrrd", "byte 8",
                 "8 of 8000000000000000 bytes");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

// ---- MetaImage ----------------------------------------------------------------------------

TEST(VolumeIo, MetaImageLocalAndCompressed) {
  const std::string head =
      "ObjectType = Image\nNDims = 3\nDimSize = 2 1 2\nElementSpacing = 0.5 1 2\n"
      "Offset = -1 0 1\nTransformMatrix = 1 0 0 0 1 0 0 0 1\nElementNumberOfChannels = 1\n";
  VolumeFile f = parse_volume(head + "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n" +
                                  bytes_of<std::uint8_t>({0, 9, 200, 255}),
                              "a.mha");
  EXPECT_EQ(f.format, VolumeFormat::MetaImage);
  EXPECT_EQ(f.element_type, "uint8");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0, 9, 200, 255}));
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{0.5, 1, 2}));
  EXPECT_EQ(f.volume.origin, (Vec3{-1, 0, 1}));
  EXPECT_EQ(f.volume.sign, FieldSign::Unknown);
  const std::string doubles = bytes_of<double>({0.1, -0.2, 1e-310, 4});
  f = parse_volume(head +
                       "ElementType = MET_DOUBLE\nCompressedData = True\n"
                       "CompressedDataSize = " +
                       std::to_string(zlib(doubles).size()) + "\nElementDataFile = LOCAL\n" +
                       zlib(doubles),
                   "c.mha");
  EXPECT_TRUE(f.compressed);
  EXPECT_EQ(f.element_type, "float64");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0.1, -0.2, 1e-310, 4}));
  f = parse_volume(head +
                       "ElementType = MET_SHORT\nElementByteOrderMSB = True\n"
                       "ElementDataFile = LOCAL\n" +
                       bytes_of<std::int16_t>({-1, 2, -300, 4}, true),
                   "b.mha");
  EXPECT_EQ(f.volume.values, (std::vector<double>{-1, 2, -300, 4}));
  f = parse_volume(
      "NDims = 3\nDimSize = 1 1 2\nElementType = MET_FLOAT\nOrigin = 1 2 3\n"
      "ElementSize = 3 3 3\nElementDataFile = LOCAL\n" +
          bytes_of<float>({1, 2}),
      "s.mha");
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{3, 3, 3}));
  EXPECT_EQ(f.volume.origin, (Vec3{1, 2, 3}));
}

TEST(VolumeIo, MetaImageSeparateData) {
  const auto dir = scratch_dir();
  const std::string head = "NDims = 3\nDimSize = 1 2 1\nElementType = MET_USHORT\n";
  write_file(dir / "v.raw", bytes_of<std::uint16_t>({7, 65535}));
  write_file(dir / "v.mhd", head + "ElementDataFile = v.raw\n");
  EXPECT_EQ(read_volume_file(dir / "v.mhd").volume.values, (std::vector<double>{7, 65535}));
  write_file(dir / "h.raw", "header!" + bytes_of<std::uint16_t>({1, 2}));
  write_file(dir / "h.mhd", head + "HeaderSize = 7\nElementDataFile = h.raw\n");
  EXPECT_EQ(read_volume_file(dir / "h.mhd").volume.values, (std::vector<double>{1, 2}));
  write_file(dir / "e.mhd", head + "HeaderSize = -1\nElementDataFile = h.raw\n");
  EXPECT_EQ(read_volume_file(dir / "e.mhd").volume.values, (std::vector<double>{1, 2}));
  write_file(dir / "z.raw", zlib(bytes_of<std::uint16_t>({5, 6})));
  write_file(dir / "z.mhd", head + "CompressedData = True\nElementDataFile = z.raw\n");
  EXPECT_EQ(read_volume_file(dir / "z.mhd").volume.values, (std::vector<double>{5, 6}));
  write_file(dir / "m.mhd", head + "ElementDataFile = missing.raw\n");
  EXPECT_THROW(read_volume_file(dir / "m.mhd"), IoError);
  write_file(dir / "c.raw", bytes_of<std::uint16_t>({1}));
  write_file(dir / "c.mhd", head + "ElementDataFile = c.raw\n");
  try {  // short data: the byte named is in the data file
    read_volume_file(dir / "c.mhd");
    ADD_FAILURE() << "read";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.source(), (dir / "c.raw").string());
    EXPECT_EQ(e.byte_offset(), 2u);
  }
  EXPECT_REFUSED(head + "ElementDataFile = v.raw\n", "v.mhd", "line 4", "cannot be followed");
  EXPECT_REFUSED(head + "ElementDataFile = LIST\n", "l.mhd", "line 4", "cannot be followed");
}

TEST(VolumeIo, MetaImageDamageNamesItsLineOrByte) {
  const std::string ok = "NDims = 3\nDimSize = 2 1 1\n";
  const std::string two = bytes_of<float>({1, 2});
  EXPECT_REFUSED(
      "NDims = 2\nDimSize = 2 1\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n" + two,
      "2d.mha", "line 1", "NDims must be 3");
  const std::string local = ok + "ElementType = MET_FLOAT\nElementDataFile = LOCAL\n";
  EXPECT_REFUSED(local + two.substr(0, 6), "cut.mha", "byte " + std::to_string(local.size() + 6),
                 "6 of 8 bytes");
  EXPECT_REFUSED(ok + "ElementType = MET_STRING\nElementDataFile = LOCAL\n" + two, "t.mha",
                 "line 3", "unsupported ElementType 'MET_STRING'");
  EXPECT_REFUSED(ok +
                     "ElementType = MET_FLOAT\nElementNumberOfChannels = 3\nElementDataFile = "
                     "LOCAL\n" +
                     two,
                 "ch.mha", "line 4", "one channel");
  EXPECT_REFUSED(ok +
                     "TransformMatrix = 0 1 0 1 0 0 0 0 1\nElementType = MET_FLOAT\n"
                     "ElementDataFile = LOCAL\n" +
                     two,
                 "rot.mha", "line 3", "rotated volumes are not supported");
  EXPECT_REFUSED(ok +
                     "Orientation = 1 0 0 0 -1 0 0 0 1\nElementType = MET_FLOAT\n"
                     "ElementDataFile = LOCAL\n" +
                     two,
                 "ori.mha", "line 3", "Orientation must be the identity");
  EXPECT_REFUSED(ok + "ElementType = MET_FLOAT\nBinaryData = False\nElementDataFile = LOCAL\n1 2",
                 "txt.mha", "line 4", "BinaryData = False");
  EXPECT_REFUSED(
      ok + "ElementType = MET_FLOAT\nElementSpacing = 1 1\nElementDataFile = LOCAL\n" + two,
      "sp.mha", "line 4", "needs 3 numbers");
  EXPECT_REFUSED(ok + "ElementType = MET_FLOAT\nHeaderSize = x\nElementDataFile = LOCAL\n" + two,
                 "hs.mha", "line 4", "whole number");
  EXPECT_REFUSED(local + bytes_of<float>({NAN, 1}), "nan.mha",
                 "byte " + std::to_string(local.size()), "value 0 is not finite");
  const std::string z = ok +
                        "ElementType = MET_FLOAT\nCompressedData = True\n"
                        "ElementDataFile = LOCAL\n";
  EXPECT_REFUSED(z + zlib(two).substr(0, 5), "tz.mha", "byte " + std::to_string(z.size() + 5),
                 "truncated");
  const auto start = std::chrono::steady_clock::now();
  const std::string huge =
      "NDims = 3\nDimSize = 100000 100000 100000\nElementType = MET_DOUBLE\n"
      "ElementDataFile = LOCAL\n";
  EXPECT_REFUSED(huge + two, "big.mha", "byte " + std::to_string(huge.size() + 8),
                 "8 of 8000000000000000 bytes");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

// ---- INR ----------------------------------------------------------------------------------

TEST(VolumeIo, InrTypesAndEndianness) {
  const std::string dims = "XDIM=2\nYDIM=1\nZDIM=1\nVDIM=1\n";
  VolumeFile f = parse_volume(
      inr_header(dims + "TYPE=unsigned fixed\nPIXSIZE=8 bits\nSCALE=2**0\nCPU=pc\n") + "\x03\xfe",
      "u8.inr");
  EXPECT_EQ(f.format, VolumeFormat::Inr);
  EXPECT_EQ(f.element_type, "uint8");
  EXPECT_EQ(f.volume.values, (std::vector<double>{3, 254}));
  EXPECT_FALSE(f.volume.has_physical_size());
  f = parse_volume(inr_header(dims + "TYPE=signed fixed\nPIXSIZE=16 bits\nCPU=sgi\n") +
                       bytes_of<std::int16_t>({-2, 1000}, true),
                   "i16.inr");
  EXPECT_EQ(f.element_type, "int16");
  EXPECT_EQ(f.volume.values, (std::vector<double>{-2, 1000}));
  f = parse_volume(inr_header(dims + "TYPE=signed fixed\nPIXSIZE=16 bits\nCPU=alpha\n") +
                       bytes_of<std::int16_t>({-2, 1000}),
                   "i16le.inr");
  EXPECT_EQ(f.volume.values, (std::vector<double>{-2, 1000}));
  f = parse_volume(inr_header(dims + "TYPE=float\nPIXSIZE=32 bits\nCPU=decm\nVX=0.5\nVY=1\nVZ=1.5\n"
                                     "TX=1\nTY=2\nTZ=3\n") +
                       bytes_of<float>({0.25f, -8}),
                   "f32.inr");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0.25, -8}));
  EXPECT_EQ(f.volume.spacing, (std::array<double, 3>{0.5, 1, 1.5}));
  EXPECT_EQ(f.volume.origin, (Vec3{1, 2, 3}));
  f = parse_volume(
      gzip(inr_header(dims + "TYPE=float\nPIXSIZE=64 bits\nCPU=sun\nVX=1\nVY=1\nVZ=1\n") +
           bytes_of<double>({0.1, 1e200}, true)),
      "f64.inr.gz");
  EXPECT_TRUE(f.compressed);
  EXPECT_EQ(f.element_type, "float64");
  EXPECT_EQ(f.volume.values, (std::vector<double>{0.1, 1e200}));
  EXPECT_TRUE(f.warnings.empty());
  // CGAL reads headers of any length up to "##}" (libcgal-demo's small-scalar.inr has 240
  // bytes); so do we, with a warning.
  f = parse_volume("#INRIMAGE-4#{\n" + dims + "TYPE=unsigned fixed\nPIXSIZE=8 bits\n##}\n\x01\x02",
                   "short.inr");
  EXPECT_EQ(f.volume.values, (std::vector<double>{1, 2}));
  ASSERT_EQ(f.warnings.size(), 1u);
  EXPECT_NE(f.warnings[0].find("not a multiple of 256"), std::string::npos);
}

TEST(VolumeIo, InrDamageNamesItsLineOrByte) {
  const std::string dims = "XDIM=2\nYDIM=1\nZDIM=1\n";
  const std::string f32 = "TYPE=float\nPIXSIZE=32 bits\n";
  EXPECT_REFUSED("#INRIMAGE-4#{\nXDIM=2\n", "e.inr", "byte 0", "no end");
  EXPECT_REFUSED(inr_header("XDIM=2\nYDIM=1\n" + f32), "z.inr", "line 1", "no ZDIM");
  EXPECT_REFUSED(inr_header(dims + "VDIM=3\n" + f32), "v.inr", "line 5", "VDIM=1");
  EXPECT_REFUSED(inr_header(dims + "TYPE=float\nPIXSIZE=16 bits\n"), "p.inr", "line 5",
                 "PIXSIZE 16");
  EXPECT_REFUSED(inr_header(dims + "TYPE=packed\nPIXSIZE=8 bits\n"), "t.inr", "line 5", "'packed'");
  EXPECT_REFUSED(inr_header(dims + f32 + "CPU=vax\n") + bytes_of<float>({1, 2}), "c.inr", "line 7",
                 "unknown INR CPU 'vax'");
  EXPECT_REFUSED(inr_header(dims + f32 + "VX=abc\n") + bytes_of<float>({1, 2}), "vx.inr", "line 7",
                 "'abc' is not a number");
  EXPECT_REFUSED(inr_header(dims + f32) + "abcde", "cut.inr", "byte 261", "5 of 8 bytes");
  EXPECT_REFUSED(inr_header(dims + f32) + bytes_of<float>({1, NAN}), "nan.inr", "byte 260",
                 "value 1 is not finite");
  const auto start = std::chrono::steady_clock::now();
  EXPECT_REFUSED(inr_header("XDIM=100000\nYDIM=100000\nZDIM=100000\n" + f32) + "abcd", "big.inr",
                 "byte 260", "4 of 4000000000000000 bytes");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST(VolumeIo, ReadsLibcgalDemosSkullCt) {
  const std::filesystem::path skull = std::filesystem::path(TPMSFILL_CGAL_IMAGES) / "skull_2.9.inr";
  if (!std::filesystem::exists(skull)) GTEST_SKIP() << "libcgal-demo is not installed";
  const VolumeFile f = read_volume_file(skull);
  const ScalarVolume& v = f.volume;
  EXPECT_EQ(f.format, VolumeFormat::Inr);
  EXPECT_EQ(f.element_type, "float32");
  EXPECT_FALSE(f.compressed);
  EXPECT_TRUE(f.warnings.empty());
  ASSERT_EQ(v.dims, (std::array<int, 3>{64, 64, 64}));
  ASSERT_EQ(v.values.size(), 64u * 64 * 64);
  // The header says VX=3.943050 VY=3.943050 VZ=3.650790, no TX/TY/TZ.
  EXPECT_EQ(v.spacing, (std::array<double, 3>{3.94305, 3.94305, 3.65079}));
  EXPECT_EQ(v.origin, Vec3{});
  EXPECT_EQ(v.sign, FieldSign::Unknown);
  const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
  EXPECT_GE(*lo, 0);
  EXPECT_LT(*lo, 1e-12);
  EXPECT_EQ(*hi, double(5.428802490234375f));
  EXPECT_EQ(v.at(10, 20, 30), double(0.147425726f));  // byte 256 + 4·(10 + 64·(20 + 64·30))
}

// ---- detection, limits, names ---------------------------------------------------------------

TEST(VolumeIo, ContentDecidesTheFormatThenTheExtension) {
  const std::string nrrd = kNrrd3 + "type: uint8\nsizes: 1 1 1\n\n\x05";
  EXPECT_EQ(parse_volume(nrrd, "misnamed.tdf").format, VolumeFormat::Nrrd);
  EXPECT_EQ(parse_volume("NDims = 3\nDimSize = 1 1 1\nElementType = MET_UCHAR\n"
                         "ElementDataFile = LOCAL\n\x05",
                         "noext")
                .format,
            VolumeFormat::MetaImage);
  EXPECT_EQ(parse_volume("1 1 1\n5\n", "plain.TDF").format, VolumeFormat::FieldText);
  try {
    parse_volume("1 1 1\n5\n", "plain.dat");
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a field file"), std::string::npos) << e.what();
  }
  // A forced format reads the bytes as that format (and says what is wrong with them).
  VolumeReadOptions text;
  text.format = VolumeFormat::FieldText;
  EXPECT_EQ(parse_volume("1 1 1\n5\n", "plain.dat", text).volume.values[0], 5);
  EXPECT_THROW(parse_volume(nrrd, "n.nrrd", text), ParseError);
  // Empty, over the limit (as given, and once inflated).
  EXPECT_THROW(parse_volume("", "e.tdf"), InputError);
  VolumeReadOptions small;
  small.max_bytes = 16;
  EXPECT_THROW(parse_volume("1 1 4\n1 2 3 4 5 6 7 8 9\n", "l.tdf", small), InputError);
  EXPECT_THROW(parse_volume(gzip(std::string(1000, ' ') + "1 1 1\n0\n"), "l.tdf.gz", small),
               InputError);
  const auto dir = scratch_dir();
  write_file(dir / "big.tdf", "1 1 4\n1 2 3 4 5 6 7 8 9\n");
  EXPECT_THROW(read_volume_file(dir / "big.tdf", small), InputError);
  EXPECT_THROW(read_volume_file(dir / "absent.tdf"), IoError);
}

TEST(VolumeIo, Names) {
  EXPECT_EQ(volume_format_name(VolumeFormat::FieldText), "field-text");
  EXPECT_EQ(volume_format_name(VolumeFormat::FieldBinary), "field-binary");
  EXPECT_EQ(volume_format_name(VolumeFormat::Nrrd), "nrrd");
  EXPECT_EQ(volume_format_name(VolumeFormat::MetaImage), "metaimage");
  EXPECT_EQ(volume_format_name(VolumeFormat::Inr), "inr");
  EXPECT_EQ(volume_format_from_extension("a/b.TDF"), VolumeFormat::FieldText);
  EXPECT_EQ(volume_format_from_extension("b.tdfb"), VolumeFormat::FieldBinary);
  EXPECT_EQ(volume_format_from_extension("b.nhdr"), VolumeFormat::Nrrd);
  EXPECT_EQ(volume_format_from_extension("b.nrrd"), VolumeFormat::Nrrd);
  EXPECT_EQ(volume_format_from_extension("b.mhd"), VolumeFormat::MetaImage);
  EXPECT_EQ(volume_format_from_extension("b.Mha"), VolumeFormat::MetaImage);
  EXPECT_EQ(volume_format_from_extension("liver.INR.GZ"), VolumeFormat::Inr);
  EXPECT_EQ(volume_format_from_extension("b.raw"), VolumeFormat::Auto);
  EXPECT_EQ(volume_format_from_extension("b.gz"), VolumeFormat::Auto);
  for (const FieldSign s : {FieldSign::Unknown, FieldSign::Signed, FieldSign::Unsigned})
    EXPECT_EQ(field_sign_from_name(field_sign_name(s)), s);
  try {
    field_sign_from_name("positive");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("positive"), std::string::npos) << what;
    EXPECT_NE(what.find("unsigned"), std::string::npos) << what;
  }
}
