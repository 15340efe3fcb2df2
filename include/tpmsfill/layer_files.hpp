/// @file layer_files.hpp
/// @brief Stage "layer files": slice()'s layers written as printers read them, one layer at a
/// time (nothing but the current layer is held).
///
///   Common Layer Interface (.cli), ASCII or binary: what laser powder-bed machines read
///   SVG: one file holding every layer (a group per layer), or one file per layer
///   PNG mask stacks: one 8-bit greyscale image per layer for DLP/SLA, solid white, with
///   antialiasing from φ (a pixel's coverage from φ at its centre)
///
/// Coordinates are millimetres, as the layers'. Files are written where the caller says; the
/// caller makes them atomic (temporary names renamed once every layer is written).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "tpmsfill/io.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

enum class LayerFormat {
  Cli,        ///< Common Layer Interface 2.0, ASCII (one file)
  CliBinary,  ///< the same, binary long commands after an ASCII header (one file)
  Svg,        ///< one SVG, a <g> per layer (one file)
  SvgLayers,  ///< one SVG per layer (a folder)
  PngLayers,  ///< one PNG mask per layer (a folder)
};

/// "cli", "cli-binary", "svg", "svg-layers", "png" (the CLI's --format names).
std::string_view layer_format_name(LayerFormat format);
/// @throws InputError  not one of those names
LayerFormat layer_format_from_name(std::string_view name);
/// Whether the format writes a folder of files (one per layer) rather than one file.
bool writes_folder(LayerFormat format);
/// How the format holds a contour's points (SliceOptions::rounding): binary CLI as floats,
/// ASCII CLI and SVG as six decimals; PNG masks hold pixels, not points (None).
CoordinateRounding layer_rounding(LayerFormat format);

struct LayerFileOptions {
  LayerFormat format = LayerFormat::Cli;
  /// The region drawn, mm (the model's box): CLI $$DIMENSION, the SVG viewBox, the PNG extent.
  Box3 bounds;
  std::uint64_t layer_count = 0;  ///< CLI $$LAYERS
  double layer = 0;               ///< thickness, mm
  double pixel = 0.05;            ///< PNG pixel size, mm (> 0)
  /// PNG layers with a material (material_layers.hpp): RGB on the SVG's material scale (blue,
  /// green, yellow) on white, for people, instead of grey = material, for printers.
  bool material_colour = false;
  std::string label = "part";  ///< CLI $$LABEL, SVG title
};

/// Writes layers to `path` (a file, or for the folder formats an existing empty folder) as
/// they come, lowest first. Folder formats name files layer_NNNNN.svg / .png (five digits or
/// more, the layer's index).
/// The bytes a stack of options.layer_count layers with `points` contour points in all (and
/// `material_triangles` drawn, a fitted solid's sections) takes in options.format: a forecast,
/// for a preflight. The text formats from their numbers' widths over options.bounds, binary CLI
/// exactly but for its header; PNG masks from their pixels, which deflate to about a byte per
/// pixel the contours cross and a hundredth of one for the rest.
double layer_file_bytes(const LayerFileOptions& options, double points,
                        double material_triangles = 0);

class LayerFileWriter {
 public:
  /// @throws InputError  bad options (pixel <= 0, an image over 2^15 pixels a side, empty
  ///                     bounds)
  /// @throws IoError     the file cannot be created
  LayerFileWriter(const std::filesystem::path& path, const LayerFileOptions& options);
  LayerFileWriter(const LayerFileWriter&) = delete;
  LayerFileWriter& operator=(const LayerFileWriter&) = delete;
  ~LayerFileWriter();

  /// @throws IoError     a write failed (disk full, ...)
  /// @throws InputError  PNG: the layer has contours but no plane field to draw from
  void add(const Layer& layer);
  /// Writes what follows the last layer and closes the file(s).
  /// @throws IoError     a write failed
  /// @throws InputError  CLI: the layers added are not options.layer_count (the file's
  ///                     $$LAYERS would lie)
  void finish();

  /// The files written so far (one, or one per layer), for the caller's report.
  const std::vector<std::filesystem::path>& files() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tpmsfill
