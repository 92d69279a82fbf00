#include "proto/message_file.h"


#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "core/file_util.h"
#include "fitbase/v1/avatar.pb.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

using ::testing::HasSubstr;


// An empty folder `name` for one test.
std::filesystem::path TempDir(const std::string& name) {
  const std::filesystem::path dir = core::ProcessTempDir() / name;
  std::filesystem::create_directories(dir);
  return dir;
}

const std::vector<std::string>& ModifierNames() {
  static const auto* names = new std::vector<std::string>{
      "stomach/stomach-pregnant-decr|incr",  "measure/measure-waist-circ-decr|incr",
      "breast/breast-dist-decr|incr",        "hip/hip-scale-depth-decr|incr",
      "buttocks/buttocks-volume-decr|incr",  "measure/measure-neck-circ-decr|incr",
      "measure/measure-hips-circ-decr|incr", "torso/torso-scale-depth-decr|incr"};
  return *names;
}

// A basis message with nested maps, inserted in forward or reverse order.
v1::AvatarBasis SampleBasis(bool reverse) {
  v1::AvatarBasis basis;
  basis.set_id("basis-1");
  basis.set_topology_id("test-topology");
  basis.mutable_mean()->set_vertex_count(1);
  for (float x : {0.25f, 1.5f, -0.125f}) basis.mutable_mean()->add_positions(x);
  basis.set_component_count(1);
  for (float x : {1.0f, 0.0f, 0.0f}) basis.add_components(x);
  basis.add_variances(0.01);
  basis.add_explained_variance_ratio(1.0);
  basis.mutable_selection()->set_component_count(1);
  v1::PopulationProvenance* population = basis.mutable_population();
  population->set_preset("women");
  population->set_seed(7);
  population->set_count(2);
  for (int p = 0; p < 2; ++p) {
    v1::AvatarParams* params = population->add_params();
    params->set_gender(0.1 * p);
    const auto& names = ModifierNames();
    for (size_t i = 0; i < names.size(); ++i) {
      const size_t k = reverse ? names.size() - 1 - i : i;
      (*params->mutable_modifiers())[names[k]] = 0.05 * static_cast<double>(k + p);
    }
  }
  return basis;
}

TEST(MessageFileTest, WriteThenReadRoundTrips) {
  const auto path = TempDir("round_trip") / "basis.pb";
  const v1::AvatarBasis original = SampleBasis(false);
  ASSERT_TRUE(WriteMessageFile(path, original).ok());
  v1::AvatarBasis read;
  const absl::Status status = ReadMessageFile(path, &read);
  ASSERT_TRUE(status.ok()) << status;
  EXPECT_EQ(SerializeDeterministically(read), SerializeDeterministically(original));
  EXPECT_EQ(read.id(), "basis-1");
  ASSERT_EQ(read.mean().positions_size(), 3);
  EXPECT_EQ(read.mean().positions(1), 1.5f);
  ASSERT_EQ(read.population().params_size(), 2);
  EXPECT_EQ(read.population().params(1).modifiers().at("hip/hip-scale-depth-decr|incr"),
            0.05 * 4);
}

TEST(MessageFileTest, EqualMessagesGiveEqualBytes) {
  const v1::AvatarBasis forward = SampleBasis(false);
  const v1::AvatarBasis backward = SampleBasis(true);
  EXPECT_EQ(SerializeDeterministically(forward), SerializeDeterministically(backward));

  const auto dir = TempDir("deterministic");
  ASSERT_TRUE(WriteMessageFile(dir / "a.pb", forward).ok());
  ASSERT_TRUE(WriteMessageFile(dir / "b.pb", backward).ok());
  auto a = core::ReadFileToString(dir / "a.pb");
  auto b = core::ReadFileToString(dir / "b.pb");
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_FALSE(a->empty());
  EXPECT_EQ(*a, *b);
  EXPECT_EQ(*a, SerializeDeterministically(forward));
}

TEST(MessageFileTest, OverwriteReplacesContentAndLeavesNoTemporaryFile) {
  const auto dir = TempDir("no_tmp");
  const auto path = dir / "weights.pb";
  v1::AvatarWeights weights;
  weights.set_basis_id("first");
  weights.add_weights(1.0);
  ASSERT_TRUE(WriteMessageFile(path, weights).ok());
  weights.set_basis_id("second");
  ASSERT_TRUE(WriteMessageFile(path, weights).ok());

  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  EXPECT_THAT(names, ::testing::ElementsAre("weights.pb"));
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));

  v1::AvatarWeights read;
  ASSERT_TRUE(ReadMessageFile(path, &read).ok());
  EXPECT_EQ(read.basis_id(), "second");
}

TEST(MessageFileTest, MissingFileIsNotFound) {
  v1::AvatarBasis basis;
  const absl::Status status = ReadMessageFile(TempDir("missing") / "absent.pb", &basis);
  EXPECT_EQ(status.code(), absl::StatusCode::kNotFound) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr("absent.pb"));
}

TEST(MessageFileTest, GarbageBytesAreInvalidArgument) {
  const auto path = TempDir("garbage") / "garbage.pb";
  // Field 1, wire type 7 (does not exist), then junk: no parser accepts it.
  ASSERT_TRUE(core::WriteFileAtomically(path, std::string("\x0f\xff\xff\xff garbage", 12)).ok());
  v1::AvatarBasis basis;
  const absl::Status status = ReadMessageFile(path, &basis);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr("garbage.pb"));
  EXPECT_THAT(std::string(status.message()), HasSubstr("fitbase.v1.AvatarBasis"));
}

TEST(MessageFileTest, TruncatedFileIsInvalidArgument) {
  const auto dir = TempDir("truncated");
  const std::string bytes = SerializeDeterministically(SampleBasis(false));
  ASSERT_GT(bytes.size(), 10u);
  ASSERT_TRUE(core::WriteFileAtomically(dir / "cut.pb", bytes.substr(0, bytes.size() - 3)).ok());
  v1::AvatarBasis basis;
  EXPECT_EQ(ReadMessageFile(dir / "cut.pb", &basis).code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fitbase::proto
