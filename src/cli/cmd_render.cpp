// `tpmsfill render IN OUT.png`: a picture of a mesh (tpmsfill::render_mesh). This file only
// parses and checks the names; the drawing is the library's.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/render.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/picture_flags.hpp"
#include "cli/thread_flags.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

struct RenderArgs {
  std::string input, output;
  PictureArgs picture;
  std::vector<int> colour, background;
  bool quiet = false;
  int threads = 0;
};

Rgb rgb(const std::vector<int>& c) {
  return {static_cast<std::uint8_t>(c[0]), static_cast<std::uint8_t>(c[1]),
          static_cast<std::uint8_t>(c[2])};
}

int run_render(const RenderArgs& args) {
  const auto threads = thread_limit(args.threads);
  RenderOptions options = picture_options(args.picture);
  if (args.colour.size() == 3) options.colour = rgb(args.colour);
  if (args.background.size() == 3) options.background = rgb(args.background);
  // Refuse a bad name, or one that would replace the input, before reading anything.
  require_png_name("OUT", args.output);
  require_writable_outputs({args.input}, {{"OUT", args.output}});

  const MeshFile file = read_mesh_file(args.input);
  print_warnings(file.warnings);
  const Image image = render_mesh(file.soup, options);
  write_png(args.output, image);
  if (!args.quiet)
    std::printf("%s -> %s (%d x %d pixels)\n", args.input.c_str(), args.output.c_str(), image.width,
                image.height);
  return kOk;
}

}  // namespace

Command add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* sub = app.add_subcommand("render", "Draw a mesh to a PNG picture");
  sub->footer(
      "An orthographic picture, shaded by two lights fixed to the camera and fitted to the "
      "mesh (or to what --clip leaves) with a 4 % margin; 2x2 supersampled. Where --clip cuts "
      "a closed solid open, the inside is drawn flat in a darker, warmer tint, so the cut reads "
      "as a section. Options go after IN and OUT.png. The same mesh and options give the same "
      "bytes whatever the thread count.\n\n"
      "Examples:\n"
      "  tpmsfill render scaffold.stl scaffold.png\n"
      "  tpmsfill render scaffold.stl top.png --view z --size 1024\n"
      "  tpmsfill render femur-lattice.stl cut.png --view 90 20 --clip x 0\n"
      "  tpmsfill render part.obj banner.png --size 1200 400 --colour 230 159 0\n\n"
      "Exit code 0: written; 2: unreadable input, bad arguments, a name not ending in .png, or "
      "nothing left after --clip (nothing is written).");
  sub->add_option("IN", args->input, "Mesh: STL, OBJ, PLY or OFF (gzip allowed) or 3MF")
      ->required();
  sub->add_option("OUT.png", args->output, "The picture (PNG, 8-bit RGB)")->required();
  add_picture_options(sub, args->picture, true);
  sub->add_option("--colour,--color", args->colour, "Surface colour R G B, 0 to 255 each")
      ->expected(3)
      ->check(between(0, 255, "0 to 255"));
  sub->add_option("--background", args->background, "Background colour R G B (default white)")
      ->expected(3)
      ->check(between(0, 255, "0 to 255"));
  add_threads_option(sub, args->threads);
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_render(*args); };
}

}  // namespace tpmsfill::cli
