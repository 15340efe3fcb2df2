// The picture flags of picture_flags.hpp.
#include "cli/picture_flags.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <tpmsfill/error.hpp>

#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

double number(const std::string& option, const std::string& text) {
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc{} || stop != end || !std::isfinite(value))
    throw InputError(option + ": '" + text + "' is not a number");
  return value;
}

}  // namespace

void add_picture_options(CLI::App* sub, PictureArgs& args, bool clip) {
  sub->add_option("--view", args.view,
                  "Where the camera looks from: iso (default: azimuth 35, elevation 25), x, y, z "
                  "(from that axis's positive side), -x, -y, -z (write --view=-x), or AZIMUTH "
                  "ELEVATION in degrees (0 0 looks along +y; 90 0 from +x; 0 90 from above)")
      ->expected(1, 2)
      ->type_name("NAME|AZ EL");
  if (clip)
    sub->add_option("--clip", args.clip,
                    "Cut the mesh open along the plane AXIS = POS (AXIS x, y or z; POS in mm) and "
                    "take away the half nearer the camera, so the inside shows")
        ->expected(2)
        ->type_name("AXIS POS");
  sub->add_option("--size", args.size,
                  "Picture size in pixels: the longer side (default 640; the other follows the "
                  "view), or WIDTH HEIGHT (the view fitted in, centred)")
      ->expected(1, 2)
      ->type_name("N|W H")
      ->check(between(16, 16384, "16 to 16384 pixels"));
}

RenderOptions picture_options(const PictureArgs& args) {
  RenderOptions o;
  if (args.view.size() == 1) {
    o.view = named_view(args.view[0]);
  } else if (args.view.size() == 2) {
    o.view = {number("--view", args.view[0]), number("--view", args.view[1])};
    if (std::abs(o.view.elevation) > 180)
      throw InputError("--view: the elevation is -180 to 180 degrees");
  }
  if (args.clip.size() == 2) {
    const std::string& axis = args.clip[0];
    if (axis != "x" && axis != "y" && axis != "z")
      throw InputError("--clip: '" + axis + "' is not an axis (x, y or z)");
    o.clip.axis = axis[0] - 'x';
    o.clip.position = number("--clip", args.clip[1]);
  }
  if (args.size.size() >= 1) o.width = args.size[0];
  if (args.size.size() == 2) o.height = args.size[1];
  return o;
}

void require_png_name(const std::string& option, const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".png")
    throw InputError(path + ": " + option + " is a PNG picture; its name ends in .png");
}

}  // namespace tpmsfill::cli
