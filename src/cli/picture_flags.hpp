// The flags that describe a picture (--view, --clip, --size), shared by `render` and
// `check --picture`, and the one check on a picture's name.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <tpmsfill/render.hpp>
#include <vector>

namespace tpmsfill::cli {

struct PictureArgs {
  std::vector<std::string> view;  ///< a name, or azimuth and elevation
  std::vector<std::string> clip;  ///< axis and position
  std::vector<int> size;          ///< the longer side, or width and height
};

/// Registers --view and --size on `sub` (and --clip when `clip`).
void add_picture_options(CLI::App* sub, PictureArgs& args, bool clip);

/// The view, clip and size the flags give, over render_mesh()'s defaults.
/// @throws InputError  a view that is neither a name nor two numbers, an elevation outside
///                     -180 to 180, a clip axis other than x, y, z, a position that is not a
///                     number
RenderOptions picture_options(const PictureArgs& args);

/// @throws InputError  "<path>: <option> is a PNG picture; its name ends in .png"
void require_png_name(const std::string& option, const std::string& path);

}  // namespace tpmsfill::cli
