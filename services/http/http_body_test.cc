#include "services/http/http_body.h"

#include "core/test_support.h"
#include "fitbase/v1/fit_service.pb.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::http {
namespace {

using core::StatusIs;

TEST(HttpBodyTest, JsonBodiesFollowTheProtobufMappingAndRefuseUnknownFields) {
  v1::TryOnRequest request;
  ASSERT_TRUE(ParseJsonBody(R"({"garment_id": "g1", "weights": {"weights": [0.5, -1]}})",
                            &request)
                  .ok());
  EXPECT_EQ(request.garment_id(), "g1");
  EXPECT_EQ(request.weights().weights_size(), 2);
  EXPECT_THAT(ParseJsonBody(R"({"garment_id": "g1", "colour": "red"})", &request),
              StatusIs(absl::StatusCode::kInvalidArgument, "not a valid TryOnRequest"));
  EXPECT_THAT(ParseJsonBody("{\"garment_id\": ", &request),
              StatusIs(absl::StatusCode::kInvalidArgument, "in JSON"));
}

TEST(HttpBodyTest, UploadsAreAnAvatarFileOrAnObjOfTheBodysTopology) {
  EXPECT_THAT(ParseUploadedAvatar("\xff\x01garbage", "application/octet-stream").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "not an avatar file (.fba)"));
  EXPECT_THAT(ParseUploadedAvatar("v 1 2\nf 1 2 3\n", "text/plain").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "the uploaded OBJ"));
  EXPECT_THAT(ParseUploadedAvatar("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "has 3 vertices"));
  // An .fba parses as the message it is; its positions are the service's to check.
  v1::Avatar avatar;
  avatar.set_format_version(1);
  avatar.mutable_positions()->set_vertex_count(3);
  auto parsed =
      ParseUploadedAvatar(avatar.SerializeAsString(), "application/octet-stream; charset=x");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->positions().vertex_count(), 3u);
}

}  // namespace
}  // namespace fitbase::http
