// The OpenIGTLink codec's cost per message (bridges/include/cobra/bridges/igtl_codec.hpp): a
// TRANSFORM encoded (what the bridge's update does per mapped pose and send period) and decoded
// (the link thread, per received pose), beside the peer libOpenIGTLink (what 3D Slicer and PLUS
// use) packing and unpacking the same message (CRC checked); and a 160 x 120 IMAGE encoded (the
// link thread, per image sent). Median and worst of the repetitions.
#include <benchmark/benchmark.h>
#include <igtlMessageHeader.h>
#include <igtlTransformMessage.h>

#include <cstring>

#include <array>
#include <cmath>
#include <vector>

#include "cobra/bridges/igtl_codec.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace cobra::bridges::igtl;
using cobra::bench::maxOf;

void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(10)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(0.05);
}

Transform sampleTransform() {
  Transform t;
  const double a = 0.3;
  t.matrix[0][0] = std::cos(a);
  t.matrix[0][1] = -std::sin(a);
  t.matrix[1][0] = std::sin(a);
  t.matrix[1][1] = std::cos(a);
  t.matrix[0][3] = 0.1;
  t.matrix[1][3] = -0.05;
  t.matrix[2][3] = 0.2;
  return t;
}

void BM_IgtlTransform_Encode(benchmark::State& state) {
  const Transform t = sampleTransform();
  std::array<std::uint8_t, kTransformMessageSize> out{};
  std::uint64_t stamp = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(encodeTransform("NeedleTip", t, ++stamp, out));
    benchmark::ClobberMemory();
  }
}

void BM_IgtlTransform_Decode(benchmark::State& state) {
  std::array<std::uint8_t, kTransformMessageSize> bytes{};
  encodeTransform("Registration", sampleTransform(), 1, bytes);
  Message m;
  for (auto _ : state) {
    benchmark::DoNotOptimize(decode(bytes, 1 << 20, m));
    benchmark::ClobberMemory();
  }
}

void BM_IgtlTransform_LibraryPack(benchmark::State& state) {
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  message->SetDeviceName("NeedleTip");
  ::igtl::Matrix4x4 matrix;
  ::igtl::IdentityMatrix(matrix);
  matrix[0][3] = 100.0F;
  for (auto _ : state) {
    message->SetMatrix(matrix);
    message->Pack();
    benchmark::DoNotOptimize(message->GetPackPointer());
  }
}

void BM_IgtlTransform_LibraryUnpack(benchmark::State& state) {
  std::array<std::uint8_t, kTransformMessageSize> bytes{};
  encodeTransform("Registration", sampleTransform(), 1, bytes);
  ::igtl::MessageHeader::Pointer header = ::igtl::MessageHeader::New();
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  ::igtl::Matrix4x4 matrix;
  for (auto _ : state) {
    header->InitPack();
    std::memcpy(header->GetPackPointer(), bytes.data(), kHeaderSize);
    header->Unpack();
    message->SetMessageHeader(header);
    message->AllocatePack();
    std::memcpy(message->GetPackBodyPointer(), bytes.data() + kHeaderSize, 48);
    benchmark::DoNotOptimize(message->Unpack(1));
    message->GetMatrix(matrix);
    benchmark::DoNotOptimize(matrix[0][3]);
  }
}

void BM_IgtlImage_Encode160x120(benchmark::State& state) {
  std::vector<std::uint8_t> pixels(160 * 120, 7);
  ImageView image;
  image.width = 160;
  image.height = 120;
  image.spacing_x = image.spacing_y = 0.3e-3;
  image.corner = sampleTransform();
  image.pixels = pixels.data();
  std::vector<std::uint8_t> out(imageMessageSize(160, 120));
  for (auto _ : state) {
    benchmark::DoNotOptimize(encodeImage("USImage", image, 1, out));
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(out.size()));
}

}  // namespace

BENCHMARK(BM_IgtlTransform_Encode)->Name("BM_IgtlTransform/encode")->Apply(configure);
BENCHMARK(BM_IgtlTransform_Decode)->Name("BM_IgtlTransform/decode")->Apply(configure);
BENCHMARK(BM_IgtlTransform_LibraryPack)->Name("BM_IgtlTransform/libopenigtlink_pack")->Apply(configure);
BENCHMARK(BM_IgtlTransform_LibraryUnpack)->Name("BM_IgtlTransform/libopenigtlink_unpack")->Apply(configure);
BENCHMARK(BM_IgtlImage_Encode160x120)->Name("BM_IgtlImage/encode_160x120")->Apply(configure);
BENCHMARK_MAIN();
