// Writes the seed inputs fuzz/make_corpus.sh cannot take from files the fitbase CLI writes:
//   fitbase_fuzz_seeds draco OUT_DIR OBJ...         Draco payloads (draco_positions_fuzzer's
//                                                   format) of each OBJ's positions, whole and
//                                                   its first vertices, at several bit depths
//   fitbase_fuzz_seeds specs OUT_DIR B.fbb G.fbg    the drape task specs of G's first size
//   fitbase_fuzz_seeds builds OUT_DIR G.fbg         build records for build_record_fuzzer
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/status_macros.h"
#include "fitbase/v1/build.pb.h"
#include "pipeline/clothing_basis_builder.h"
#include "proto/draco_codec.h"
#include "proto/message_file.h"
#include "workers/drape_task_spec.h"

namespace fitbase {
namespace {

absl::Status WriteSeed(const std::filesystem::path& dir, const std::string& name,
                       const std::string& bytes) {
  return core::WriteFileAtomically(dir / name, bytes);
}

absl::Status WriteDracoSeeds(const std::filesystem::path& dir,
                             const std::vector<std::string>& objs) {
  for (const std::string& obj : objs) {
    ASSIGN_OR_RETURN(core::GarmentMesh mesh, core::ReadGarmentObj(obj));
    const core::Positions& positions = mesh.mesh.positions;
    // The fuzzer's 2-byte count tops out at 65,536 vertices.
    for (const int64_t count : {int64_t{1}, int64_t{7}, int64_t{200}, positions.rows()}) {
      if (count > positions.rows() || count > 65536) continue;
      std::vector<float> xyz;
      for (Eigen::Index v = 0; v < count; ++v) {
        for (int axis = 0; axis < 3; ++axis) xyz.push_back(static_cast<float>(positions(v, axis)));
      }
      for (const int bits : {4, 11, 20}) {
        ASSIGN_OR_RETURN(v1::EncodedPositions encoded,
                         proto::EncodeDracoPositions(xyz, {.quantization_bits = bits}));
        const int64_t stored = count - 1;
        std::string seed = {static_cast<char>(stored & 0xff), static_cast<char>(stored >> 8)};
        seed += encoded.draco().data();
        RETURN_IF_ERROR(WriteSeed(
            dir,
            absl::StrCat(std::filesystem::path(obj).stem().string(), "-", count, "-", bits),
            seed));
      }
    }
  }
  return absl::OkStatus();
}

absl::Status WriteSpecSeeds(const std::filesystem::path& dir, const std::string& basis_path,
                            const std::string& garment_path) {
  v1::AvatarBasis basis;
  RETURN_IF_ERROR(proto::ReadMessageFile(basis_path, &basis));
  v1::Garment garment;
  RETURN_IF_ERROR(proto::ReadMessageFile(garment_path, &garment));
  if (garment.sizes().empty()) return absl::InvalidArgumentError("the garment has no sizes");
  const pipeline::ClothingBuildSpec spec{
      .avatar_basis = &basis, .garment = &garment, .size = garment.sizes(0).name()};
  ASSIGN_OR_RETURN(pipeline::ClothingPlan plan, pipeline::PlanClothingBasis(spec));
  for (size_t i = 0; i < plan.tasks.size(); ++i) {
    RETURN_IF_ERROR(WriteSeed(dir, absl::StrCat("spec-", i),
                              proto::SerializeDeterministically(
                                  workers::DrapeTaskToSpec(plan.tasks[i]))));
  }
  return absl::OkStatus();
}

absl::Status WriteBuildSeeds(const std::filesystem::path& dir, const std::string& garment_path) {
  v1::Garment garment;
  RETURN_IF_ERROR(proto::ReadMessageFile(garment_path, &garment));
  v1::Build build;
  build.set_build_id("build-000001");
  build.set_tenant("fuzz");
  v1::BuildRequest& request = *build.mutable_request();
  request.set_garment_id(garment.id());
  for (const v1::GarmentSize& size : garment.sizes()) request.add_sizes(size.name());
  request.add_methods("linear");
  request.set_homotopy_steps(2);
  request.set_relax_steps(2);
  RETURN_IF_ERROR(WriteSeed(dir, "build-all-sizes", proto::SerializeDeterministically(build)));
  request.clear_sizes();
  request.add_sizes(garment.sizes(0).name());
  request.set_avatar_basis_id(garment.avatar_basis_id());
  request.set_example_scale(0.5);
  RETURN_IF_ERROR(WriteSeed(dir, "build-one-size", proto::SerializeDeterministically(build)));
  request.add_methods("kernel");
  request.set_sampled_drapes(3);
  request.set_sample_seed(7);
  return WriteSeed(dir, "build-kernel", proto::SerializeDeterministically(build));
}

absl::Status Run(const std::vector<std::string>& args) {
  if (args.size() >= 3 && args[0] == "draco") {
    return WriteDracoSeeds(args[1], std::vector<std::string>(args.begin() + 2, args.end()));
  }
  if (args.size() == 4 && args[0] == "specs") return WriteSpecSeeds(args[1], args[2], args[3]);
  if (args.size() == 3 && args[0] == "builds") return WriteBuildSeeds(args[1], args[2]);
  return absl::InvalidArgumentError(
      "usage: fitbase_fuzz_seeds draco OUT_DIR OBJ... | specs OUT_DIR B.fbb G.fbg | builds "
      "OUT_DIR G.fbg");
}

}  // namespace
}  // namespace fitbase

int main(int argc, char** argv) {
  const absl::Status status = fitbase::Run(std::vector<std::string>(argv + 1, argv + argc));
  if (!status.ok()) {
    std::cerr << "fitbase_fuzz_seeds: " << status.message() << "\n";
    return 1;
  }
  return 0;
}
