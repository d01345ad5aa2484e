// The IG's answer, the CIGI 3.3 and 4.0 Start of Frame (host_sdk cigi.h):
// golden bytes written from the layout (docs/CIGI.md), both byte orders, the
// packets after it skipped, and the refusals.
#include <vector>

#include <gtest/gtest.h>

#include "atmo/cigi.h"

namespace c = atmo::cigi;
using Bytes = std::vector<uint8_t>;

namespace {

// Big-endian (the magic 0x80 0x00), by hand from the table, not by the encoder.
const Bytes kGoldenBig = {
    0x65, 0x18, 0x03, 0x05, 0x07, 0x3d, 0x80, 0x00,  // id 101, 24 bytes, v3, db 5, status 7, minor 3|erm|ts|operate
    0x01, 0x02, 0x03, 0x04, 0x00, 0x01, 0x00, 0x00,  // IG frame 0x01020304, timestamp 0x10000
    0x00, 0x00, 0x01, 0x02, 0x00, 0x00, 0x00, 0x00,  // last host frame 0x102, reserved
};
// The same from a little-endian IG (0x00 0x80).
const Bytes kGoldenLittle = {
    0x65, 0x18, 0x03, 0x05, 0x07, 0x3d, 0x00, 0x80,
    0x04, 0x03, 0x02, 0x01, 0x00, 0x00, 0x01, 0x00,
    0x02, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
};

// CIGI 4.0 (CCL 4.0 CigiSOFV4): 16-bit size and id 0xFFFF first; big-endian (the size's zero byte first).
const Bytes kGolden40Big = {
    0x00, 0x18, 0xff, 0xff, 0x04, 0x05, 0x07, 0x0d,  // 24 bytes, id 0xFFFF, v4, db 5, status 7, minor 0|erm|ts|operate
    0x01, 0x02, 0x03, 0x04, 0x00, 0x01, 0x00, 0x00,  // IG frame 0x01020304, timestamp 0x10000
    0x00, 0x00, 0x01, 0x02, 0x00, 0x00, 0x00, 0x00,  // last host frame 0x102, condition flags, reserved
};
const Bytes kGolden40Little = {
    0x18, 0x00, 0xff, 0xff, 0x04, 0x05, 0x07, 0x0d,
    0x04, 0x03, 0x02, 0x01, 0x00, 0x00, 0x01, 0x00,
    0x02, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
};

c::StartOfFrame golden() {
  c::StartOfFrame s;
  s.minor_version = 3;
  s.database_id = 5;
  s.ig_status = 7;
  s.ig_mode = 1;
  s.timestamp_valid = true;
  s.earth_model_host_defined = true;
  s.ig_frame_number = 0x01020304;
  s.timestamp_ticks = 0x10000;
  s.last_host_frame_number = 0x102;
  return s;
}

void expect_refused(const Bytes& b, size_t offset, const std::string& field, const std::string& words) {
  const c::IgMessage m = c::decode_ig_message(b);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error->offset, offset) << m.error->message;
  EXPECT_EQ(m.error->field, field) << m.error->message;
  EXPECT_NE(m.error->message.find(words), std::string::npos) << m.error->message;
  EXPECT_TRUE(m.skipped.empty());
  EXPECT_EQ(m.sof, c::StartOfFrame{});
}

}  // namespace

c::StartOfFrame golden40() {
  c::StartOfFrame s = golden();
  s.minor_version = 0;
  return s;
}

TEST(CigiStartOfFrame, EncodesTheGoldenBytesInBothOrders) {
  EXPECT_EQ(c::encode_start_of_frame(golden(), c::ByteOrder::Big), kGoldenBig);
  EXPECT_EQ(c::encode_start_of_frame(golden(), c::ByteOrder::Little), kGoldenLittle);
  EXPECT_EQ(c::encode_start_of_frame(golden40(), c::ByteOrder::Big, 4), kGolden40Big);
  EXPECT_EQ(c::encode_start_of_frame(golden40(), c::ByteOrder::Little, 4), kGolden40Little);
  EXPECT_THROW(c::encode_start_of_frame(golden(), c::ByteOrder::Big, 2), std::invalid_argument);
}

TEST(CigiStartOfFrame, DecodesTheCigi40GoldenBytesInBothOrders) {
  for (const auto& [bytes, order] :
       {std::pair{kGolden40Big, c::ByteOrder::Big}, {kGolden40Little, c::ByteOrder::Little}}) {
    const c::IgMessage m = c::decode_ig_message(bytes);
    ASSERT_TRUE(m.ok()) << m.error->message;
    EXPECT_EQ(m.version.major, 4);
    EXPECT_EQ(m.version.minor, 0);
    EXPECT_EQ(m.byte_order, order);
    EXPECT_EQ(m.sof, golden40());
  }
  // 4.0 packets after it: 16-bit size and id; a second Start of Frame refused.
  Bytes b = kGolden40Little;
  b.insert(b.end(), {16, 0, 0x01, 0x10});  // a 4.0 response (id 0x1001), 16 bytes
  b.resize(b.size() + 12, 0);
  c::IgMessage m = c::decode_ig_message(b);
  ASSERT_TRUE(m.ok()) << m.error->message;
  ASSERT_EQ(m.skipped.size(), 1u);
  EXPECT_EQ(m.skipped[0].packet_id, 0x1001u);
  EXPECT_EQ(m.skipped[0].offset, 24u);
  b = kGolden40Big;
  b.insert(b.end(), kGolden40Big.begin(), kGolden40Big.end());
  expect_refused(b, 24, "packet id", "a second Start of Frame");
  b = kGolden40Big;
  b.insert(b.end(), {0, 2, 0x10, 0x01});
  expect_refused(b, 24, "packet size", "size 2 is below the 4-byte header");
  b = kGolden40Big;
  b[4] = 3;
  expect_refused(b, 0, "major version", "version 3 in a CIGI 4.0 Start of Frame");
  b = kGolden40Little;
  b.resize(20);
  expect_refused(b, 0, "packet size", "size 24 runs past the datagram's end (20 bytes left)");
}

TEST(CigiStartOfFrame, DecodesTheGoldenBytesInBothOrders) {
  for (const auto& [bytes, order] : {std::pair{kGoldenBig, c::ByteOrder::Big}, {kGoldenLittle, c::ByteOrder::Little}}) {
    const c::IgMessage m = c::decode_ig_message(bytes);
    ASSERT_TRUE(m.ok()) << m.error->message;
    EXPECT_EQ(m.version.major, 3);
    EXPECT_EQ(m.byte_order, order);
    EXPECT_EQ(m.sof, golden());
    EXPECT_TRUE(m.skipped.empty());
  }
}

TEST(CigiStartOfFrame, RoundTripsEveryField) {
  c::StartOfFrame s;
  s.minor_version = 2;
  s.database_id = -128;
  s.ig_status = 255;
  s.ig_mode = 3;
  s.ig_frame_number = 0xFFFFFFFF;
  s.timestamp_ticks = 0x80000001;
  s.last_host_frame_number = 0xDEADBEEF;
  for (uint8_t major : {3, 4})
    for (c::ByteOrder order : {c::ByteOrder::Big, c::ByteOrder::Little}) {
      const c::IgMessage m = c::decode_ig_message(c::encode_start_of_frame(s, order, major));
      ASSERT_TRUE(m.ok()) << m.error->message;
      EXPECT_EQ(m.version.major, major);
      EXPECT_EQ(m.sof, s);
    }
  s.ig_mode = 4;
  EXPECT_THROW(c::encode_start_of_frame(s, c::ByteOrder::Big), std::invalid_argument);
}

TEST(CigiStartOfFrame, PacketsAfterItAreSkippedBySize) {
  Bytes b = kGoldenBig;
  b.insert(b.end(), {102, 16});  // a HAT/HOT Response's id and size, zero body
  b.resize(b.size() + 14, 0);
  b.insert(b.end(), {250, 4, 0, 0});  // a user packet
  const c::IgMessage m = c::decode_ig_message(b);
  ASSERT_TRUE(m.ok()) << m.error->message;
  EXPECT_EQ(m.sof, golden());
  ASSERT_EQ(m.skipped.size(), 2u);
  EXPECT_EQ(m.skipped[0].packet_id, 102u);
  EXPECT_EQ(m.skipped[0].offset, 24u);
  EXPECT_EQ(m.skipped[1].packet_id, 250u);
  EXPECT_EQ(m.skipped[1].offset, 40u);
}

TEST(CigiStartOfFrame, Refusals) {
  expect_refused({}, 0, "datagram", "empty datagram");
  // A host's IG Control sent back is not an IG message.
  c::IgControl ig;
  expect_refused(c::encode({3, 3}, c::ByteOrder::Big, {ig}), 0, "Start of Frame", "must be a Start of Frame");
  Bytes b = kGoldenBig;
  b.resize(20);
  expect_refused(b, 0, "packet size", "size 24 runs past the datagram's end (20 bytes left)");
  b = kGoldenBig;
  b[1] = 16;
  expect_refused(b, 0, "packet size", "CIGI 3.0/3.1 Start of Frame");
  b[1] = 12;
  expect_refused(b, 0, "packet size", "(truncated)");
  b = kGoldenBig;
  b[2] = 4;
  expect_refused(b, 0, "major version", "version 4 in a CIGI 3 Start of Frame");
  b = kGoldenBig;
  b[6] = 0x12;
  expect_refused(b, 0, "byte-swap magic", "0x12 0x00 are neither");
  b = kGoldenBig;
  b.insert(b.end(), {102, 0});
  expect_refused(b, 24, "packet size", "size 0");
  b = kGoldenBig;
  b.insert(b.end(), {102, 16, 0, 0});
  expect_refused(b, 24, "packet size", "size 16 runs past the datagram's end (4 bytes left)");
  b = kGoldenBig;
  b.push_back(102);
  expect_refused(b, 24, "packet header", "1 bytes left");
  b = kGoldenBig;
  b.insert(b.end(), kGoldenBig.begin(), kGoldenBig.end());
  expect_refused(b, 24, "packet id", "a second Start of Frame");
}

TEST(CigiStartOfFrame, EveryTruncationAndByteChangeIsHandled) {
  Bytes full = kGoldenLittle;
  full.insert(full.end(), {102, 8, 1, 2, 3, 4, 5, 6});
  for (size_t n = 0; n < full.size(); ++n) {
    const Bytes cut(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
    const c::IgMessage m = c::decode_ig_message(cut);
    EXPECT_EQ(m.ok(), n == 24) << n << " bytes";  // the Start of Frame alone is a whole message
    if (!m.ok() && n > 0) {
      EXPECT_LT(m.error->offset, n);
    }
  }
  for (size_t i = 0; i < full.size(); ++i) {
    for (int v : {0x00, 0x01, 0x65, 0x80, 0xFF}) {
      Bytes b = full;
      b[i] = uint8_t(v);
      const c::IgMessage m = c::decode_ig_message(b);
      if (!m.ok()) {
        EXPECT_LT(m.error->offset, b.size());
      }
    }
  }
}
