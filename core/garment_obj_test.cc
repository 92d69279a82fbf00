#include "core/garment_obj.h"

#include <algorithm>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_split.h"
#include "core/file_util.h"
#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

std::filesystem::path TempPath(const std::string& name) { return ProcessTempDir() / name; }

absl::StatusOr<GarmentMesh> ReadText(const std::string& name, absl::string_view text) {
  const std::filesystem::path path = TempPath(name);
  if (absl::Status status = WriteFileAtomically(path, text); !status.ok()) return status;
  return ReadGarmentObj(path);
}

void ExpectSameGarment(const GarmentMesh& a, const GarmentMesh& b) {
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  EXPECT_EQ(a.mesh.faces, b.mesh.faces);
  EXPECT_EQ(a.texcoords, b.texcoords);
  EXPECT_EQ(a.face_texcoord_indices, b.face_texcoord_indices);
}

std::vector<std::filesystem::path> ShippedObjFiles() {
  std::vector<std::filesystem::path> files;
  for (const auto& dir : std::filesystem::directory_iterator(TestDataDir() / "clothes")) {
    files.push_back(dir.path() / (dir.path().filename().string() + ".obj"));
  }
  std::sort(files.begin(), files.end());
  return files;
}

struct ObjLines {
  std::vector<absl::string_view> vertices;
  std::vector<absl::string_view> texcoords;
  std::vector<absl::string_view> faces;
};

ObjLines Classify(absl::string_view text) {
  ObjLines lines;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    if (absl::StartsWith(line, "v ")) lines.vertices.push_back(line);
    if (absl::StartsWith(line, "vt ")) lines.texcoords.push_back(line);
    if (absl::StartsWith(line, "f ")) lines.faces.push_back(line);
  }
  return lines;
}

// The corners of `garment`'s face `face` as `v/vt` text, 1-based as in the file.
std::string FaceText(const GarmentMesh& garment, int64_t face) {
  size_t corner = 0;
  for (int64_t f = 0; f < face; ++f) corner += static_cast<size_t>(garment.mesh.faces.sizes[f]);
  std::string text = "f";
  for (int32_t k = 0; k < garment.mesh.faces.sizes[face]; ++k, ++corner) {
    absl::StrAppend(&text, " ", garment.mesh.faces.indices[corner] + 1, "/",
                    garment.face_texcoord_indices[corner] + 1);
  }
  return text;
}

TEST(GarmentObjTest, ReadsShippedGarmentsInFileOrder) {
  const std::vector<std::filesystem::path> files = ShippedObjFiles();
  ASSERT_EQ(files.size(), 12u);
  for (const std::filesystem::path& path : files) {
    auto text = ReadFileToString(path);
    ASSERT_TRUE(text.ok()) << text.status();
    const ObjLines lines = Classify(*text);
    auto garment = ReadGarmentObj(path);
    ASSERT_TRUE(garment.ok()) << garment.status();
    EXPECT_EQ(garment->mesh.vertex_count(), static_cast<int64_t>(lines.vertices.size())) << path;
    EXPECT_EQ(garment->mesh.faces.face_count(), static_cast<int64_t>(lines.faces.size())) << path;
    EXPECT_EQ(garment->texcoords.rows(), static_cast<int64_t>(lines.texcoords.size())) << path;
    EXPECT_EQ(garment->face_texcoord_indices.size(), garment->mesh.faces.indices.size());
    // The shipped files write every corner as v/vt, so the first and last faces read back as
    // their own lines.
    EXPECT_EQ(FaceText(*garment, 0), lines.faces.front()) << path;
    EXPECT_EQ(FaceText(*garment, garment->mesh.faces.face_count() - 1), lines.faces.back()) << path;
    const std::vector<absl::string_view> last_vertex =
        absl::StrSplit(lines.vertices.back(), ' ', absl::SkipEmpty());
    ASSERT_EQ(last_vertex.size(), 4u);
    for (int axis = 0; axis < 3; ++axis) {
      double expected = 0.0;
      ASSERT_TRUE(absl::SimpleAtod(last_vertex[axis + 1], &expected));
      EXPECT_EQ(garment->mesh.positions(garment->mesh.vertex_count() - 1, axis), expected);
    }
  }
}

TEST(GarmentObjTest, ReadsEveryCornerForm) {
  auto garment = ReadText("corners.obj",
                          "# corners\n"
                          "mtllib x.mtl\n"
                          "o shirt\n"
                          "v 0 0 0\r\n"
                          "v 1 0 0 1\n"
                          "v 1 1 0 0.5 0.5 0.5\n"
                          "v\t0 1 0\n"
                          "vt 0 0\n"
                          "vt 1 0 0\n"
                          "vt 1 1\n"
                          "vt 0 1\n"
                          "vn 0 0 1\n"
                          "g panel\n"
                          "usemtl cloth\n"
                          "s off\n"
                          "f 1/2 3/4 4/1 2/3\n"
                          "f 1 2 3\n"
                          "f 1//1 2//1 3//1\n"
                          "f 4/3/1 3/2/1 1/1/1\n"
                          "f -1/-1 -2/-2 -3/-3\n"
                          "l 1 2\n");
  ASSERT_TRUE(garment.ok()) << garment.status();
  EXPECT_EQ(garment->mesh.vertex_count(), 4);
  EXPECT_EQ(garment->mesh.positions.row(2), Eigen::RowVector3d(1, 1, 0));
  EXPECT_EQ(garment->mesh.positions.row(3), Eigen::RowVector3d(0, 1, 0));
  ASSERT_EQ(garment->texcoords.rows(), 4);
  EXPECT_EQ(garment->texcoords.row(1), Eigen::RowVector2d(1, 0));
  EXPECT_EQ(garment->mesh.faces.sizes, (std::vector<int32_t>{4, 3, 3, 3, 3}));
  EXPECT_EQ(garment->mesh.faces.indices,
            (std::vector<int32_t>{0, 2, 3, 1, 0, 1, 2, 0, 1, 2, 3, 2, 0, 3, 2, 1}));
  EXPECT_EQ(garment->face_texcoord_indices,
            (std::vector<int32_t>{1, 3, 0, 2, -1, -1, -1, -1, -1, -1, 2, 1, 0, 3, 2, 1}));
  EXPECT_TRUE(garment->mesh.topology_id.empty());
}

TEST(GarmentObjTest, NonManifoldFacesKeepTheirVertices) {
  // Three quads sharing one edge: OpenMesh would duplicate vertices for the third.
  auto garment = ReadText("fin.obj",
                          "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 1 0\n"
                          "v 0 0 1\nv 0 1 1\n"
                          "f 1 3 4 2\nf 2 6 5 1\nf 1 2 8 7\n");
  ASSERT_TRUE(garment.ok()) << garment.status();
  EXPECT_EQ(garment->mesh.vertex_count(), 8);
  EXPECT_EQ(garment->mesh.faces.face_count(), 3);
  EXPECT_EQ(garment->mesh.faces.indices,
            (std::vector<int32_t>{0, 2, 3, 1, 1, 5, 4, 0, 0, 1, 7, 6}));
}

TEST(GarmentObjTest, MalformedInputNamesTheLine) {
  struct Case {
    const char* text;
    const char* expected;
  };
  for (const Case& c : {
           Case{"v 0 0 0\nv nan 0 0\n", "line 2: coordinate is not a finite number"},
           Case{"v 0 0 0\nv 0 inf 0\n", "line 2: coordinate is not a finite number"},
           Case{"v 0 0 0\nv 0 0 x\n", "line 2: coordinate is not a finite number"},
           Case{"v 1 2\n", "line 1: expected 'v x y z'"},
           Case{"v 1 2 3 4 5\n", "line 1: expected 'v x y z'"},
           Case{"v 0 0 0\nvt 0 nan\n", "line 2: texture coordinate is not a finite number"},
           Case{"v 0 0 0\nvt 0\n", "line 2: expected 'vt u v'"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4: corner '0' does not name"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "corner '4' does not name one of the 3"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "corner '-4' does not name"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "corner 'x' does not name"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1.5\n", "corner '1.5' does not name"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "line 4: a face needs at least 3 corners"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n",
                "corner '3/2' does not name one of the 1 texture coordinates"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",
                "corner '1//1' does not name one of the 0 normals"},
           Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2/ 3/\n", "corner '1/' is malformed"},
           Case{"# nothing\n", "has no vertices"},
       }) {
    auto garment = ReadText("bad.obj", c.text);
    ASSERT_FALSE(garment.ok()) << c.text;
    EXPECT_THAT(garment, StatusIs(absl::StatusCode::kInvalidArgument, c.expected)) << c.text;
    EXPECT_THAT(garment, StatusIs(absl::StatusCode::kInvalidArgument, "bad.obj")) << c.text;
  }
}

TEST(GarmentObjTest, ParsesTextAsReadingItsFileWould) {
  const std::filesystem::path path = ShippedObjFiles().front();
  auto text = ReadFileToString(path);
  ASSERT_TRUE(text.ok()) << text.status();
  auto read = ReadGarmentObj(path);
  ASSERT_TRUE(read.ok()) << read.status();
  auto parsed = ParseGarmentObj(*text, "upload 7");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  ExpectSameGarment(*parsed, *read);
}

TEST(GarmentObjTest, ParseErrorsNameTheGivenNameAndLine) {
  EXPECT_THAT(ParseGarmentObj("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "retailer/shirt.obj"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "retailer/shirt.obj line 3: corner '3' does not name one of the 2"));
  EXPECT_THAT(ParseGarmentObj("", "upload 7"),
              StatusIs(absl::StatusCode::kInvalidArgument, "upload 7 has no vertices"));
}

TEST(GarmentObjTest, MissingFileIsNotFound) {
  EXPECT_EQ(ReadGarmentObj(TempPath("missing.obj")).status().code(), absl::StatusCode::kNotFound);
}

TEST(GarmentObjTest, WriteThenReadIsExactForEveryShippedGarment) {
  for (const std::filesystem::path& path : ShippedObjFiles()) {
    auto garment = ReadGarmentObj(path);
    ASSERT_TRUE(garment.ok()) << garment.status();
    const std::filesystem::path copy = TempPath(path.filename().string());
    ASSERT_TRUE(WriteGarmentObj(copy, *garment).ok());
    EXPECT_FALSE(std::filesystem::exists(copy.string() + ".tmp"));
    auto read = ReadGarmentObj(copy);
    ASSERT_TRUE(read.ok()) << read.status();
    ExpectSameGarment(*read, *garment);
  }
}

GarmentMesh SmallGarment() {
  GarmentMesh garment;
  garment.mesh.positions.resize(5, 3);
  garment.mesh.positions << 0, 0, 0, 1.5, 0, 0, 1, 1.25, 0, 0, 1, 0, 0.5, 0.5, -0.001;
  // A quad starting at corner 2 and a triangle: a writer that rotates corners fails.
  garment.mesh.faces.sizes = {4, 3};
  garment.mesh.faces.indices = {2, 3, 0, 1, 2, 1, 4};
  garment.texcoords.resize(3, 2);
  garment.texcoords << 0, 0, 0.25, 1, 1, 0.125;
  garment.face_texcoord_indices = {0, 1, 2, 1, -1, -1, -1};
  return garment;
}

TEST(GarmentObjTest, WritesVtCornersOnlyWhereTheyExist) {
  const GarmentMesh garment = SmallGarment();
  const std::filesystem::path path = TempPath("small.obj");
  ASSERT_TRUE(WriteGarmentObj(path, garment).ok());
  auto text = ReadFileToString(path);
  ASSERT_TRUE(text.ok());
  EXPECT_TRUE(absl::StrContains(*text, "\nf 3/1 4/2 1/3 2/2\nf 3 2 5\n")) << *text;
  EXPECT_TRUE(absl::StrContains(*text, "\nv 0.5 0.5 -0.001\n")) << *text;
  EXPECT_TRUE(absl::StrContains(*text, "\nvt 0.25 1\n")) << *text;
  auto read = ReadGarmentObj(path);
  ASSERT_TRUE(read.ok()) << read.status();
  ExpectSameGarment(*read, garment);

  GarmentMesh untextured = SmallGarment();
  untextured.texcoords.resize(0, 2);
  untextured.face_texcoord_indices.clear();
  ASSERT_TRUE(WriteGarmentObj(path, untextured).ok());
  text = ReadFileToString(path);
  ASSERT_TRUE(text.ok());
  EXPECT_FALSE(absl::StrContains(*text, "vt")) << *text;
  EXPECT_TRUE(absl::StrContains(*text, "\nf 3 4 1 2\nf 3 2 5\n")) << *text;
}

TEST(GarmentObjTest, WriteRejectsInconsistentGarmentsAndKeepsTheOldFile) {
  const std::filesystem::path path = TempPath("keep.obj");
  ASSERT_TRUE(WriteGarmentObj(path, SmallGarment()).ok());
  auto before = ReadFileToString(path);
  ASSERT_TRUE(before.ok());

  std::vector<GarmentMesh> bad(6, SmallGarment());
  bad[0].mesh.positions(1, 1) = std::nan("");
  bad[1].face_texcoord_indices.pop_back();
  bad[2].face_texcoord_indices[0] = 3;
  bad[3].mesh.faces.indices[6] = 5;
  bad[4].mesh.faces.sizes = {4, 2};
  bad[5].mesh.faces.sizes = {4, 4};
  for (const GarmentMesh& garment : bad) {
    EXPECT_THAT(WriteGarmentObj(path, garment),
                StatusIs(absl::StatusCode::kInvalidArgument, "cannot write"));
  }
  auto after = ReadFileToString(path);
  ASSERT_TRUE(after.ok());
  EXPECT_EQ(*after, *before);
}

}  // namespace
}  // namespace fitbase::core
