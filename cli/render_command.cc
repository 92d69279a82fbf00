// fitbase render: front and side pictures of a body and its garments, to judge a fit by eye.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "absl/strings/string_view.h"
#include "cli/cli_context.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/mesh_render.h"
#include "core/obj_io.h"
#include "core/status_macros.h"
#include "pipeline/png_file.h"
#include "pipeline/skin_visibility.h"

namespace fitbase::cli {
namespace {

constexpr int kMinHeight = 64;
constexpr int kMaxHeight = 4096;

// Grey-beige, so every saturated garment colour stands apart from the skin.
const Eigen::Vector3d kBodyColor(0.80, 0.74, 0.66);
const std::vector<Eigen::Vector3d> kGarmentColors = {
    {0.15, 0.35, 0.85}, {0.85, 0.15, 0.15}, {0.10, 0.65, 0.25},
    {0.95, 0.55, 0.05}, {0.60, 0.20, 0.75}, {0.05, 0.70, 0.75},
};

// Where the picture marks the skin that shows where the reference garment shows cloth: the
// body through the cloth, and a line along the reference's edges (its hem or neckline elsewhere).
const Eigen::Vector3d kInsideSkinColor(1.0, 0.0, 1.0);
const Eigen::Vector3d kEdgeSkinColor(1.0, 0.85, 0.0);

struct RenderFlags {
  std::string body;
  std::vector<std::string> garments;
  std::string reference_garment;
  std::string reference_body;
  std::string values;
  std::string range;
  int height = 600;
  std::string out;
};

absl::Status Flagged(absl::string_view flag, const absl::Status& status) {
  return absl::Status(status.code(), absl::StrCat(flag, ": ", status.message()));
}

absl::Status RequireFile(absl::string_view flag, const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    return absl::NotFoundError(absl::StrCat(flag, ": no file ", path));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::pair<double, double>> ParseRange(const std::string& text) {
  const std::vector<std::string> parts = absl::StrSplit(text, ',');
  double min = 0;
  double max = 0;
  if (parts.size() != 2 || !absl::SimpleAtod(parts[0], &min) || !absl::SimpleAtod(parts[1], &max) ||
      !std::isfinite(min) || !std::isfinite(max)) {
    return absl::InvalidArgumentError(
        absl::StrCat("--range is '", text, "'; expected MIN,MAX (two finite numbers)"));
  }
  if (!(min < max)) {
    return absl::InvalidArgumentError(
        absl::StrCat("--range is '", text, "'; MIN must be below MAX"));
  }
  return std::make_pair(min, max);
}

// One finite number per line (blank lines and surrounding spaces allowed).
absl::StatusOr<Eigen::VectorXd> ReadValues(const std::string& path) {
  ASSIGN_OR_RETURN(const std::string text, core::ReadFileToString(path));
  std::vector<double> values;
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    ++line_number;
    line = absl::StripAsciiWhitespace(line);
    if (line.empty()) continue;
    double value = 0;
    if (!absl::SimpleAtod(line, &value) || !std::isfinite(value)) {
      return absl::InvalidArgumentError(absl::StrCat("--values ", path, " line ", line_number,
                                                     ": '", line, "' is not a finite number"));
    }
    values.push_back(value);
  }
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

// The visible skin of the garment on --body where --reference-garment on its body shows cloth,
// printed, and where it is, for MarkSkin. body_triangles: body.faces triangulated.
absl::StatusOr<pipeline::SkinPicture> MeasureAgainstReference(
    const RenderFlags& flags, const core::Mesh& body, const core::Triangles& body_triangles,
    const core::Mesh& garment) {
  core::Mesh reference_body = body;
  if (!flags.reference_body.empty()) {
    absl::StatusOr<core::Mesh> read = core::ReadObj(flags.reference_body);
    if (!read.ok()) return Flagged("--reference-body", read.status());
    reference_body = *std::move(read);
  }
  absl::StatusOr<core::GarmentMesh> reference = core::ReadGarmentObj(flags.reference_garment);
  if (!reference.ok()) return Flagged("--reference-garment", reference.status());
  const core::Triangles garment_triangles = core::Triangulate(garment.faces);
  const core::Triangles reference_body_triangles = core::Triangulate(reference_body.faces);
  const core::Triangles reference_triangles = core::Triangulate(reference->mesh.faces);
  pipeline::SkinPicture picture;
  ASSIGN_OR_RETURN(
      const pipeline::SkinVisibility skin,
      pipeline::MeasureVisibleSkin(
          {&reference_body.positions, &reference_body_triangles, &reference->mesh.positions,
           &reference_triangles},
          {&body.positions, &body_triangles, &garment.positions, &garment_triangles},
          flags.height, &picture));
  std::cout << absl::StrFormat(
      "visible skin against %s: %.2f%% of its %d cloth pixels, %.2f%% inside the cloth (more "
      "than %.0f mm from its edges; magenta), the rest along its edges (yellow)\n",
      flags.reference_garment, 100 * skin.share(), skin.cloth_pixels, 100 * skin.inside_share(),
      1000 * pipeline::kClothEdgeBand);
  return picture;
}

void MarkSkin(const pipeline::SkinPicture& picture, core::RenderedImage& image) {
  for (size_t i = 0; i < picture.pixels.size(); ++i) {
    if (picture.pixels[i] == pipeline::SkinPixel::kNone) continue;
    const Eigen::Vector3d& color =
        picture.pixels[i] == pipeline::SkinPixel::kInside ? kInsideSkinColor : kEdgeSkinColor;
    for (int c = 0; c < 3; ++c) {
      image.rgb[3 * i + c] = static_cast<uint8_t>(std::lround(255 * color[c]));
    }
  }
}

absl::Status RunRender(const RenderFlags& flags) {
  if (flags.height < kMinHeight || flags.height > kMaxHeight) {
    return absl::InvalidArgumentError(
        absl::StrCat("--height is ", flags.height, "; expected ", kMinHeight, "..", kMaxHeight));
  }
  if (flags.values.empty() != flags.range.empty()) {
    return absl::InvalidArgumentError("--values and --range go together: give both or neither");
  }
  if (!flags.values.empty() && flags.garments.empty()) {
    return absl::InvalidArgumentError("--values colours the first --garment; none was given");
  }
  if (!flags.reference_body.empty() && flags.reference_garment.empty()) {
    return absl::InvalidArgumentError(
        "--reference-body is the body of --reference-garment; give that garment too");
  }
  if (!flags.reference_garment.empty() && flags.garments.size() != 1) {
    return absl::InvalidArgumentError(absl::StrCat(
        "--reference-garment is compared with one --garment; ", flags.garments.size(),
        " were given"));
  }
  RETURN_IF_ERROR(RequireFile("--body", flags.body));
  for (const std::string& garment : flags.garments) {
    RETURN_IF_ERROR(RequireFile("--garment", garment));
  }
  if (!flags.reference_garment.empty()) {
    RETURN_IF_ERROR(RequireFile("--reference-garment", flags.reference_garment));
  }
  if (!flags.reference_body.empty()) {
    RETURN_IF_ERROR(RequireFile("--reference-body", flags.reference_body));
  }

  std::vector<core::RenderLayer> layers(1);
  absl::StatusOr<core::Mesh> body = core::ReadObj(flags.body);
  if (!body.ok()) return Flagged("--body", body.status());
  layers[0].mesh = *std::move(body);
  layers[0].color = kBodyColor;
  for (size_t i = 0; i < flags.garments.size(); ++i) {
    // Not ReadObj: OpenMesh would split a garment's non-manifold seams and renumber vertices,
    // and --values is one per vertex in the file's order.
    absl::StatusOr<core::GarmentMesh> garment = core::ReadGarmentObj(flags.garments[i]);
    if (!garment.ok()) return Flagged("--garment", garment.status());
    core::RenderLayer& layer = layers.emplace_back();
    layer.mesh = std::move(garment->mesh);
    layer.color = kGarmentColors[i % kGarmentColors.size()];
  }
  if (!flags.values.empty()) {
    RETURN_IF_ERROR(RequireFile("--values", flags.values));
    ASSIGN_OR_RETURN(const auto range, ParseRange(flags.range));
    ASSIGN_OR_RETURN(Eigen::VectorXd values, ReadValues(flags.values));
    core::RenderLayer& layer = layers[1];
    if (values.size() != layer.mesh.vertex_count()) {
      return absl::InvalidArgumentError(
          absl::StrCat("--values ", flags.values, " has ", values.size(), " numbers; --garment ",
                       flags.garments[0], " has ", layer.mesh.vertex_count(), " vertices"));
    }
    layer.values = std::move(values);
    layer.value_min = range.first;
    layer.value_max = range.second;
  }

  const core::Triangles body_triangles = core::Triangulate(layers[0].mesh.faces);
  core::RenderOptions options;
  options.height = flags.height;
  std::optional<pipeline::SkinPicture> skin_picture;
  if (!flags.reference_garment.empty()) {
    ASSIGN_OR_RETURN(skin_picture, MeasureAgainstReference(flags, layers[0].mesh, body_triangles,
                                                           layers[1].mesh));
    options.frame = skin_picture->frame;
  }
  ASSIGN_OR_RETURN(core::RenderedImage image, core::RenderFrontAndSide(layers, options));
  if (skin_picture.has_value()) MarkSkin(*skin_picture, image);
  RETURN_IF_ERROR(pipeline::WritePng(flags.out, image.width, image.height, image.rgb));
  std::cout << absl::StrFormat("wrote %s (%dx%d: front view, side view from +X%s)\n", flags.out,
                               image.width, image.height, flags.values.empty() ? "" : ", legend");
  for (size_t i = 1; i < layers.size(); ++i) {
    const core::Triangles garment_triangles = core::Triangulate(layers[i].mesh.faces);
    ASSIGN_OR_RETURN(const pipeline::SkinVisibility skin,
                     pipeline::MeasureSkinThroughCloth({&layers[0].mesh.positions, &body_triangles,
                                                        &layers[i].mesh.positions,
                                                        &garment_triangles},
                                                       flags.height));
    std::cout << absl::StrFormat(
        "skin through %s: %.2f%% of its %d cloth pixels (body within %.0f mm before the cloth)\n",
        flags.garments[i - 1], 100 * skin.share(), skin.cloth_pixels,
        1000 * pipeline::kClothCoverDepth);
  }
  if (!flags.values.empty()) {
    const std::vector<double> limits =
        core::ColorScaleLimits(layers[1].value_min, layers[1].value_max);
    std::cout << "legend, bottom to top (values outside the range take the end bands):\n";
    for (int band = 0; band < core::kColorScaleBands; ++band) {
      const Eigen::Vector3d c = core::ColorScaleColor(0.5 * (limits[band] + limits[band + 1]),
                                                      limits.front(), limits.back());
      std::cout << absl::StrFormat(
          "  band %d #%02x%02x%02x: %g to %g\n", band + 1,
          static_cast<int>(std::lround(255 * c[0])), static_cast<int>(std::lround(255 * c[1])),
          static_cast<int>(std::lround(255 * c[2])), limits[band], limits[band + 1]);
    }
  }
  return absl::OkStatus();
}

}  // namespace

void AddRenderCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<RenderFlags>();
  CLI::App* render =
      app.add_subcommand("render", "Front and side pictures (PNG) of a body and its garments");
  render->add_option("--body", flags->body, "Body OBJ (meters, +Y up, +Z front)")->required();
  render->add_option("--garment", flags->garments, "Garment OBJ, drawn over the body (repeatable)");
  render->add_option("--reference-garment", flags->reference_garment,
                     "Garment OBJ the --garment is judged against (e.g. the drape): the skin the "
                     "--garment shows where this one shows cloth is printed and marked on the "
                     "picture");
  render->add_option("--reference-body", flags->reference_body,
                     "Body OBJ of --reference-garment (default: --body)");
  render->add_option("--values", flags->values,
                     "One number per vertex of the first garment (e.g. ease, meters), colouring "
                     "it through the scale");
  render->add_option("--range", flags->range, "MIN,MAX of the colour scale for --values");
  render->add_option(
      "--height", flags->height,
      absl::StrCat("Image height in pixels, ", kMinHeight, "..", kMaxHeight, " (default: 600)"));
  render->add_option("--out", flags->out, "PNG to write")->required();
  render->callback([&context, flags] { context.action = [flags] { return RunRender(*flags); }; });
}

}  // namespace fitbase::cli
