// The OpenIGTLink codec against libOpenIGTLink (what 3D Slicer and PLUS speak): messages it packs
// decode to the right records (mm -> m), messages we encode unpack in it with their CRC, and every
// rejection reason, with seeded garbage that must never crash or decode.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "cobra/bridges/igtl_codec.hpp"
#include "igtl_test_peer.hpp"

namespace cobra::bridges::igtl {
namespace {

constexpr std::size_t kLimit = 1 << 20;

IgtlError decodeAll(const std::vector<std::uint8_t>& bytes, Message& out, std::size_t limit = kLimit) {
  return decode(bytes, limit, out);
}

TEST(IgtlCodec, Crc64IsEcma182AsOpenIgtlinkComputesIt) {
  const std::string check = "123456789";
  EXPECT_EQ(crc64({reinterpret_cast<const std::uint8_t*>(check.data()), check.size()}), 0x6C40DF5F0B497347ULL);
}

TEST(IgtlCodec, DecodesALibraryTransformInMetres) {
  const auto bytes = test::transformBytes("Registration", 0.3F, 12.5F, -40.25F, 100.0F);
  Message m;
  ASSERT_EQ(decodeAll(bytes, m), IgtlError::Ok);
  EXPECT_EQ(m.type, MessageType::Transform);
  EXPECT_EQ(m.device.view(), "Registration");
  const float c = std::cos(0.3F), s = std::sin(0.3F);
  EXPECT_DOUBLE_EQ(m.transform.matrix[0][0], c);
  EXPECT_DOUBLE_EQ(m.transform.matrix[0][1], -s);
  EXPECT_DOUBLE_EQ(m.transform.matrix[1][0], s);
  EXPECT_DOUBLE_EQ(m.transform.matrix[2][2], 1.0);
  EXPECT_NEAR(m.transform.matrix[0][3], 0.0125, 1e-12);
  EXPECT_NEAR(m.transform.matrix[1][3], -0.04025, 1e-12);
  EXPECT_NEAR(m.transform.matrix[2][3], 0.1, 1e-12);
}

TEST(IgtlCodec, EncodedTransformUnpacksInTheLibraryInMillimetres) {
  Transform t;
  const double a = 0.5;
  t.matrix[0][0] = std::cos(a);
  t.matrix[0][2] = std::sin(a);
  t.matrix[2][0] = -std::sin(a);
  t.matrix[2][2] = std::cos(a);
  t.matrix[0][3] = 0.25;
  t.matrix[1][3] = -0.125;
  t.matrix[2][3] = 0.0625;
  std::vector<std::uint8_t> bytes(kTransformMessageSize);
  ASSERT_EQ(encodeTransform("NeedleTip", t, wireTimestamp(1'500'000'000), bytes), kTransformMessageSize);
  auto m = test::unpack<::igtl::TransformMessage>(bytes);
  ASSERT_TRUE(m);
  EXPECT_STREQ(m->GetDeviceName(), "NeedleTip");
  ::igtl::Matrix4x4 matrix;
  m->GetMatrix(matrix);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(matrix[r][c], t.matrix[r][c], 1e-6) << r << c;
  EXPECT_FLOAT_EQ(matrix[0][3], 250.0F);
  EXPECT_FLOAT_EQ(matrix[1][3], -125.0F);
  EXPECT_FLOAT_EQ(matrix[2][3], 62.5F);
  unsigned sec = 0, frac = 0;
  ::igtl::TimeStamp::Pointer ts = ::igtl::TimeStamp::New();
  m->GetTimeStamp(ts);
  ts->GetTimeStamp(&sec, &frac);
  EXPECT_EQ(sec, 1U);
  EXPECT_NEAR(frac, 500'000'000U, 1U);  // the library gives the fraction in ns
}

TEST(IgtlCodec, DecodesALibraryPointListInMetres) {
  const auto bytes = test::pointBytes("Plan", {{"entry", "plan", 10.0F, 20.0F, 30.0F},
                                               {"target", "plan", -5.5F, 0.0F, 80.0F}});
  Message m;
  ASSERT_EQ(decodeAll(bytes, m), IgtlError::Ok);
  EXPECT_EQ(m.type, MessageType::Point);
  EXPECT_EQ(m.device.view(), "Plan");
  ASSERT_EQ(m.points.count, 2U);
  EXPECT_EQ(m.points.points[0].name.view(), "entry");
  EXPECT_EQ(m.points.points[1].name.view(), "target");
  EXPECT_EQ(m.points.points[1].group.view(), "plan");
  EXPECT_NEAR(m.points.points[0].position[2], 0.03, 1e-12);
  EXPECT_NEAR(m.points.points[1].position[0], -0.0055, 1e-12);
}

TEST(IgtlCodec, KeepsTheFirst32PointsOfALongerList) {
  std::vector<test::PeerPoint> points;
  for (int i = 0; i < 40; ++i) points.push_back({"p" + std::to_string(i), "g", static_cast<float>(i), 0.0F, 0.0F});
  Message m;
  ASSERT_EQ(decodeAll(test::pointBytes("Plan", points), m), IgtlError::Ok);
  EXPECT_EQ(m.points.total, 40U);
  ASSERT_EQ(m.points.count, kMaxPoints);
  EXPECT_EQ(m.points.points[31].name.view(), "p31");
}

TEST(IgtlCodec, DecodesStringAndStatus) {
  Message m;
  ASSERT_EQ(decodeAll(test::stringBytes("Request", "START"), m), IgtlError::Ok);
  EXPECT_EQ(m.type, MessageType::String);
  EXPECT_EQ(m.device.view(), "Request");
  EXPECT_EQ(m.text.view(), "START");
  ASSERT_EQ(decodeAll(test::statusBytes("Slicer", 2, -7, "E_NAV", "no plan yet"), m), IgtlError::Ok);
  EXPECT_EQ(m.type, MessageType::Status);
  EXPECT_EQ(m.status.code, 2);
  EXPECT_EQ(m.status.subcode, -7);
  EXPECT_EQ(m.status.error_name.view(), "E_NAV");
  EXPECT_EQ(m.status.text.view(), "no plan yet");
}

TEST(IgtlCodec, EncodedStringAndStatusUnpackInTheLibrary) {
  std::vector<std::uint8_t> bytes(512);
  bytes.resize(encodeString("Event", "e_nav_started", 0, bytes));
  auto s = test::unpack<::igtl::StringMessage>(bytes);
  ASSERT_TRUE(s);
  EXPECT_STREQ(s->GetDeviceName(), "Event");
  EXPECT_STREQ(s->GetString(), "e_nav_started");
  EXPECT_EQ(s->GetEncoding(), 3);

  bytes.assign(512, 0);
  bytes.resize(encodeStatus("TaskState", 1, 0, "", "root.puncturing.insert", 0, bytes));
  auto st = test::unpack<::igtl::StatusMessage>(bytes);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->GetCode(), 1);
  EXPECT_STREQ(st->GetStatusString(), "root.puncturing.insert");
}

TEST(IgtlCodec, EncodedImageUnpacksWithItsSizeSpacingAndCentredMatrix) {
  constexpr std::size_t w = 4, h = 3;
  std::vector<std::uint8_t> pixels(w * h);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(10 * i);
  ImageView image;
  image.width = w;
  image.height = h;
  image.spacing_x = 0.5e-3;
  image.spacing_y = 0.25e-3;
  // The image plane: columns along world y, rows along world -x, at (0.1, 0.2, 0.3) m.
  image.corner.matrix[0][0] = 0; image.corner.matrix[0][1] = -1; image.corner.matrix[0][2] = 0;
  image.corner.matrix[1][0] = 1; image.corner.matrix[1][1] = 0; image.corner.matrix[1][2] = 0;
  image.corner.matrix[2][0] = 0; image.corner.matrix[2][1] = 0; image.corner.matrix[2][2] = 1;
  image.corner.matrix[0][3] = 0.1; image.corner.matrix[1][3] = 0.2; image.corner.matrix[2][3] = 0.3;
  image.pixels = pixels.data();
  std::vector<std::uint8_t> bytes(imageMessageSize(w, h));
  ASSERT_EQ(encodeImage("USImage", image, 0, bytes), bytes.size());
  auto m = test::unpack<::igtl::ImageMessage>(bytes);
  ASSERT_TRUE(m);
  int size[3];
  m->GetDimensions(size);
  EXPECT_EQ(size[0], 4);
  EXPECT_EQ(size[1], 3);
  EXPECT_EQ(size[2], 1);
  EXPECT_EQ(m->GetScalarType(), ::igtl::ImageMessage::TYPE_UINT8);
  float spacing[3];
  m->GetSpacing(spacing);
  EXPECT_FLOAT_EQ(spacing[0], 0.5F);
  EXPECT_FLOAT_EQ(spacing[1], 0.25F);
  float normals[3][3];
  m->GetNormals(normals);  // normals[r][c]: component r of the (unit) direction of index c
  EXPECT_NEAR(normals[1][0], 1.0, 1e-6);   // columns along y
  EXPECT_NEAR(normals[0][1], -1.0, 1e-6);  // rows along -x
  EXPECT_NEAR(normals[2][2], 1.0, 1e-6);   // the slice normal
  float origin[3];
  m->GetOrigin(origin);  // the centre: corner + 1.5 columns * 0.5 mm along y, 1 row * 0.25 mm along -x
  EXPECT_NEAR(origin[0], 100.0 - 0.25, 1e-4);
  EXPECT_NEAR(origin[1], 200.0 + 0.75, 1e-4);
  EXPECT_NEAR(origin[2], 300.0, 1e-4);
  const auto* data = static_cast<const std::uint8_t*>(m->GetScalarPointer());
  EXPECT_EQ(std::vector<std::uint8_t>(data, data + w * h), pixels);
}

TEST(IgtlCodec, EncodersRefuseTooSmallBuffersAndBadArguments) {
  std::vector<std::uint8_t> small(kTransformMessageSize - 1);
  EXPECT_EQ(encodeTransform("X", Transform{}, 0, small), 0U);
  Transform nan;
  nan.matrix[0][3] = std::nan("");
  std::vector<std::uint8_t> bytes(4096);
  EXPECT_EQ(encodeTransform("X", nan, 0, bytes), 0U);
  ImageView empty;
  EXPECT_EQ(encodeImage("X", empty, 0, bytes), 0U);
}

// A version 2 message (OpenIGTLink protocol 3) made of a version 1 one: the extended header
// before its content, `metadata` bytes after it, the sizes and the CRC made right.
std::vector<std::uint8_t> version2(std::vector<std::uint8_t> v1, std::uint16_t extended, std::uint16_t metadata_header,
                                   std::uint32_t metadata) {
  std::vector<std::uint8_t> out(v1.begin(), v1.begin() + kHeaderSize);
  out[1] = 2;
  const std::uint8_t ext[12] = {static_cast<std::uint8_t>(extended >> 8), static_cast<std::uint8_t>(extended),
                                static_cast<std::uint8_t>(metadata_header >> 8), static_cast<std::uint8_t>(metadata_header),
                                static_cast<std::uint8_t>(metadata >> 24), static_cast<std::uint8_t>(metadata >> 16),
                                static_cast<std::uint8_t>(metadata >> 8), static_cast<std::uint8_t>(metadata),
                                0, 0, 0, 42};
  out.insert(out.end(), ext, ext + 12);
  out.insert(out.end(), v1.begin() + kHeaderSize, v1.end());
  out.resize(out.size() + metadata_header + metadata, 0x5A);  // the metadata, skipped
  const std::uint64_t body = out.size() - kHeaderSize;
  const std::uint64_t crc = crc64(std::span<const std::uint8_t>(out).subspan(kHeaderSize));
  for (int i = 0; i < 8; ++i) {
    out[42 + i] = static_cast<std::uint8_t>(body >> (56 - 8 * i));
    out[50 + i] = static_cast<std::uint8_t>(crc >> (56 - 8 * i));
  }
  return out;
}

TEST(IgtlCodec, ReadsVersion2MessagesSkippingTheExtendedHeaderAndMetadata) {
  Message m;
  ASSERT_EQ(decodeAll(version2(test::stringBytes("Request", "START"), 12, 10, 24), m), IgtlError::Ok);
  EXPECT_EQ(m.text.view(), "START");
  ASSERT_EQ(decodeAll(version2(test::transformBytes("Registration", 0.0F, 1, 2, 3), 12, 0, 0), m), IgtlError::Ok);
  EXPECT_NEAR(m.transform.matrix[2][3], 0.003, 1e-12);
  // Sizes that do not fit the body.
  EXPECT_EQ(decodeAll(version2(test::stringBytes("Request", "START"), 8, 0, 0), m), IgtlError::BadBody);
  auto bytes = version2(test::stringBytes("Request", "START"), 12, 0, 0);
  bytes[kHeaderSize + 7] = 200;  // metadata of 200 bytes in a body of 21
  const std::uint64_t crc = crc64(std::span<const std::uint8_t>(bytes).subspan(kHeaderSize));
  for (int i = 0; i < 8; ++i) bytes[50 + i] = static_cast<std::uint8_t>(crc >> (56 - 8 * i));
  EXPECT_EQ(decodeAll(bytes, m), IgtlError::BadBody);
}

TEST(IgtlCodec, ABadCrcIsRejected) {
  auto bytes = test::transformBytes("Registration", 0.0F, 1, 2, 3);
  bytes[kHeaderSize + 5] ^= 0x40;
  Message m;
  EXPECT_EQ(decodeAll(bytes, m), IgtlError::BadCrc);
}

TEST(IgtlCodec, EveryTruncationIsRejected) {
  const auto bytes = test::pointBytes("Plan", {{"a", "g", 1, 2, 3}});
  Message m;
  for (std::size_t n = 0; n < bytes.size(); ++n)
    EXPECT_EQ(decode(std::span<const std::uint8_t>(bytes.data(), n), kLimit, m), IgtlError::Truncated) << n;
}

TEST(IgtlCodec, AnOversizedBodyIsRejectedBeforeItIsRead) {
  const auto bytes = test::pointBytes("Plan", {{"a", "g", 1, 2, 3}, {"b", "g", 1, 2, 3}});
  Message m;
  EXPECT_EQ(decode(bytes, 2 * kPointElementSize - 1, m), IgtlError::Oversized);
  EXPECT_EQ(decode(bytes, 2 * kPointElementSize, m), IgtlError::Ok);
}

TEST(IgtlCodec, AnUnknownTypeIsRejected) {
  Message m;
  EXPECT_EQ(decodeAll(test::positionBytes("Tracker"), m), IgtlError::UnknownType);
}

TEST(IgtlCodec, ABadHeaderIsRejected) {
  auto bytes = test::stringBytes("Request", "START");
  bytes[1] = 3;  // version 3
  Message m;
  EXPECT_EQ(decodeAll(bytes, m), IgtlError::BadHeader);
  bytes = test::stringBytes("Request", "START");
  bytes[2 + 7] = 'X';  // a character after the type name's NUL padding began
  EXPECT_EQ(decodeAll(bytes, m), IgtlError::BadHeader);
  bytes = test::stringBytes("Request", "START");
  bytes[14] = 0x07;  // a control character in the device name
  EXPECT_EQ(decodeAll(bytes, m), IgtlError::BadHeader);
}

TEST(IgtlCodec, MalformedBodiesAreRejected) {
  Message m;
  // A POINT body that is not whole elements; its CRC made right so that the body is what fails.
  auto bytes = test::pointBytes("Plan", {{"a", "g", 1, 2, 3}});
  bytes.pop_back();
  const std::uint64_t body = bytes.size() - kHeaderSize;
  for (int i = 0; i < 8; ++i) bytes[42 + i] = static_cast<std::uint8_t>(body >> (56 - 8 * i));
  const std::uint64_t crc = crc64(std::span<const std::uint8_t>(bytes).subspan(kHeaderSize));
  for (int i = 0; i < 8; ++i) bytes[50 + i] = static_cast<std::uint8_t>(crc >> (56 - 8 * i));
  EXPECT_EQ(decodeAll(bytes, m), IgtlError::BadBody);
  // A TRANSFORM whose matrix is no rotation (scaled by 2).
  ::igtl::TransformMessage::Pointer t = ::igtl::TransformMessage::New();
  t->SetDeviceName("Registration");
  ::igtl::Matrix4x4 matrix;
  ::igtl::IdentityMatrix(matrix);
  matrix[0][0] = 2.0F;
  t->SetMatrix(matrix);
  EXPECT_EQ(decodeAll(test::bytesOf(t.GetPointer()), m), IgtlError::BadBody);
}

TEST(IgtlCodec, SeededGarbageAndMutationsNeverCrashAndNeverDecodeAsValid) {
  std::mt19937 rng(20261129);
  const std::vector<std::vector<std::uint8_t>> valid = {
      test::transformBytes("Registration", 0.1F, 1, 2, 3), test::pointBytes("Plan", {{"a", "g", 1, 2, 3}}),
      test::stringBytes("Request", "START"), test::statusBytes("S", 1, 0, "", "ok")};
  Message m;
  for (int i = 0; i < 3000; ++i) {
    std::vector<std::uint8_t> bytes;
    if (i % 2 == 0) {
      bytes.resize(rng() % 400);
      for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
      EXPECT_NE(decode(bytes, kLimit, m), IgtlError::Ok) << "random bytes never make a valid header";
    } else {
      bytes = valid[rng() % valid.size()];
      const std::size_t at = rng() % bytes.size();
      bytes[at] ^= static_cast<std::uint8_t>(1U << (rng() % 8));
      // Only a flip in the device name (another printable name) or the timestamp leaves a valid
      // message: the version, type, size and CRC fields and the body are all checked.
      if (decode(bytes, kLimit, m) == IgtlError::Ok) {
        EXPECT_TRUE(at >= 14 && at < 42) << "byte " << at;
      }
    }
  }
}

}  // namespace
}  // namespace cobra::bridges::igtl
