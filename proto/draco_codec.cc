#include "proto/draco_codec.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "draco/compression/config/compression_shared.h"
#include "draco/compression/decode.h"
#include "draco/compression/expert_encode.h"
#include "draco/compression/point_cloud/point_cloud_decoder.h"
#include "draco/point_cloud/point_cloud.h"

namespace fitbase::proto {
namespace {

// Draco's quantization transform accepts 1..30 bits.
constexpr int kMinQuantizationBits = 1;
constexpr int kMaxQuantizationBits = 30;

absl::Status CheckFinite(std::span<const float> xyz, absl::string_view what) {
  const auto bad = std::find_if(xyz.begin(), xyz.end(), [](float v) { return !std::isfinite(v); });
  if (bad == xyz.end()) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(what, " vertex ", (bad - xyz.begin()) / 3,
                                                 " has a non-finite coordinate"));
}

// Draco quantizes every axis on one grid: (2^bits - 1) steps over the longest side of the
// bounding box, each coordinate rounded to the nearest step. On top of that half step, its
// float32 arithmetic (subtracting the minimum, scaling, and back) costs a few ulps of the
// coordinates.
double MaxQuantizationError(std::span<const float> xyz, int bits) {
  double longest_side = 0;
  double max_abs = 0;
  for (int axis = 0; axis < 3; ++axis) {
    double low = std::numeric_limits<double>::infinity();
    double high = -low;
    for (size_t i = axis; i < xyz.size(); i += 3) {
      low = std::min<double>(low, xyz[i]);
      high = std::max<double>(high, xyz[i]);
    }
    longest_side = std::max(longest_side, high - low);
    max_abs = std::max({max_abs, std::abs(low), std::abs(high)});
  }
  const double step = longest_side / static_cast<double>((int64_t{1} << bits) - 1);
  return 0.5 * step + 4.0 * std::numeric_limits<float>::epsilon() * (max_abs + longest_side);
}

absl::StatusOr<std::vector<float>> DecodeRaw(const v1::RawPositions& raw, int64_t vertex_count) {
  if (raw.xyz_size() != 3 * vertex_count) {
    return absl::InvalidArgumentError(absl::StrCat("raw positions have ", raw.xyz_size(),
                                                   " values for ", vertex_count,
                                                   " vertices; expected ", 3 * vertex_count));
  }
  std::vector<float> xyz(raw.xyz().begin(), raw.xyz().end());
  RETURN_IF_ERROR(CheckFinite(xyz, "raw positions:"));
  return xyz;
}

// Refuses what would decode into the wrong order or the wrong size, from the header and the
// point count that follows it, before Draco allocates for that count.
absl::Status CheckDracoLayout(const std::string& data, int64_t vertex_count) {
  draco::DecoderBuffer buffer;
  buffer.Init(data.data(), data.size());
  draco::DracoHeader header;
  if (const draco::Status status = draco::PointCloudDecoder::DecodeHeader(&buffer, &header);
      !status.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "Draco positions (", data.size(), " bytes) are not a Draco bitstream: ",
        status.error_msg_string()));
  }
  if (header.encoder_type != draco::POINT_CLOUD) {
    return absl::InvalidArgumentError(
        "Draco positions are a mesh, whose encoders may reorder and split vertices; encode a "
        "point cloud with POINT_CLOUD_SEQUENTIAL_ENCODING (faces travel separately)");
  }
  if (header.encoder_method != draco::POINT_CLOUD_SEQUENTIAL_ENCODING) {
    return absl::InvalidArgumentError(
        "Draco positions use the kd-tree encoding, which reorders points; encode with "
        "POINT_CLOUD_SEQUENTIAL_ENCODING");
  }
  // With metadata, the point count sits behind a variable-length block.
  if (header.flags & METADATA_FLAG_MASK) {
    return absl::InvalidArgumentError("Draco positions carry metadata; encode without it");
  }
  int32_t point_count = 0;
  if (!buffer.Decode(&point_count)) {
    return absl::InvalidArgumentError("Draco positions end before their point count");
  }
  if (point_count != vertex_count) {
    return absl::InvalidArgumentError(absl::StrCat("Draco positions hold ", point_count,
                                                   " points; expected ", vertex_count));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<float>> DecodeDraco(const v1::DracoPositions& draco_positions,
                                               int64_t vertex_count) {
  const std::string& data = draco_positions.data();
  RETURN_IF_ERROR(CheckDracoLayout(data, vertex_count));
  draco::DecoderBuffer buffer;
  buffer.Init(data.data(), data.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodePointCloudFromBuffer(&buffer);
  if (!decoded.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("Draco positions do not decode: ",
                                                   decoded.status().error_msg_string()));
  }
  const draco::PointCloud& cloud = *decoded.value();
  if (cloud.num_points() != vertex_count) {
    return absl::InvalidArgumentError(absl::StrCat("Draco positions decode to ",
                                                   cloud.num_points(), " points; expected ",
                                                   vertex_count));
  }
  const draco::PointAttribute* attribute =
      cloud.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (attribute == nullptr || attribute->num_components() != 3 ||
      attribute->data_type() != draco::DT_FLOAT32) {
    return absl::InvalidArgumentError(
        "Draco positions have no POSITION attribute of 3 float32 components");
  }
  std::vector<float> xyz(3 * vertex_count);
  for (draco::PointIndex point(0); point < cloud.num_points(); ++point) {
    const draco::AttributeValueIndex value = attribute->mapped_index(point);
    if (value.value() >= attribute->size() ||
        !attribute->ConvertValue<float>(value, 3, &xyz[3 * point.value()])) {
      return absl::InvalidArgumentError(
          absl::StrCat("Draco positions have no value for point ", point.value()));
    }
  }
  RETURN_IF_ERROR(CheckFinite(xyz, "Draco positions:"));
  return xyz;
}

}  // namespace

v1::EncodedPositions EncodeRawPositions(std::span<const float> xyz) {
  v1::EncodedPositions message;
  message.set_vertex_count(static_cast<uint32_t>(xyz.size() / 3));
  message.mutable_raw()->mutable_xyz()->Assign(xyz.begin(), xyz.end());
  return message;
}

absl::StatusOr<v1::EncodedPositions> EncodeDracoPositions(std::span<const float> xyz,
                                                          const DracoSettings& settings) {
  const int bits = settings.quantization_bits;
  if (bits < kMinQuantizationBits || bits > kMaxQuantizationBits) {
    return absl::InvalidArgumentError(absl::StrCat("Draco quantization_bits is ", bits,
                                                   "; expected ", kMinQuantizationBits, " to ",
                                                   kMaxQuantizationBits));
  }
  if (xyz.size() % 3 != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(xyz.size(), " position values are not 3 per vertex"));
  }
  const int64_t vertex_count = static_cast<int64_t>(xyz.size() / 3);
  if (vertex_count == 0 || vertex_count > std::numeric_limits<int32_t>::max()) {
    return absl::InvalidArgumentError(
        absl::StrCat("cannot Draco-encode ", vertex_count, " vertices"));
  }
  RETURN_IF_ERROR(CheckFinite(xyz, "positions:"));

  draco::PointCloud cloud;
  cloud.set_num_points(static_cast<draco::PointIndex::ValueType>(vertex_count));
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32,
                /*normalized=*/false, 3 * sizeof(float), 0);
  const int attribute_id =
      cloud.AddAttribute(position, /*identity_mapping=*/true, static_cast<uint32_t>(vertex_count));
  cloud.attribute(attribute_id)->buffer()->Write(0, xyz.data(), xyz.size_bytes());

  draco::ExpertEncoder encoder(cloud);
  encoder.SetEncodingMethod(draco::POINT_CLOUD_SEQUENTIAL_ENCODING);
  encoder.SetAttributeQuantization(attribute_id, bits);
  draco::EncoderBuffer buffer;
  if (const draco::Status status = encoder.EncodeToBuffer(&buffer); !status.ok()) {
    return absl::InternalError(
        absl::StrCat("Draco encoding failed: ", status.error_msg_string()));
  }

  v1::EncodedPositions message;
  message.set_vertex_count(static_cast<uint32_t>(vertex_count));
  v1::DracoPositions* draco_positions = message.mutable_draco();
  draco_positions->set_data(buffer.data(), buffer.size());
  draco_positions->set_quantization_bits(static_cast<uint32_t>(bits));
  draco_positions->set_max_error_m(static_cast<float>(MaxQuantizationError(xyz, bits)));
  return message;
}

absl::StatusOr<std::vector<float>> DecodePositions(const v1::EncodedPositions& positions,
                                                   int64_t expected_vertex_count) {
  if (positions.vertex_count() != expected_vertex_count) {
    return absl::InvalidArgumentError(absl::StrCat("positions have vertex_count ",
                                                   positions.vertex_count(), "; expected ",
                                                   expected_vertex_count));
  }
  switch (positions.encoding_case()) {
    case v1::EncodedPositions::kRaw:
      return DecodeRaw(positions.raw(), expected_vertex_count);
    case v1::EncodedPositions::kDraco:
      return DecodeDraco(positions.draco(), expected_vertex_count);
    case v1::EncodedPositions::ENCODING_NOT_SET:
      break;
  }
  return absl::InvalidArgumentError("positions have neither raw nor draco data");
}

}  // namespace fitbase::proto
