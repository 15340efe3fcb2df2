// `tpmsfill`: the command line. It parses arguments, calls the library and turns library
// exceptions into one line on stderr and an exit code; everything else lives in the library.
#include <csignal>
#include <cstdio>
#include <exception>
#include <string>
#include <tpmsfill/error.hpp>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/memory_policy.hpp"
#include "cli/printable.hpp"
#include "cli/progress_flag.hpp"
#include "cli/ranks.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/usage_errors.hpp"
#include "io/interrupt_cleanup.hpp"

namespace {

int run(int argc, char** argv) {
  using namespace tpmsfill::cli;
  CLI::App app{
      "tpmsfill fills triangle meshes with TPMS lattices and proves that what it writes is a "
      "closed 2-manifold.\n"
      "Reads and writes STL (ASCII or binary), OBJ, PLY and OFF, also gzip-compressed, and 3MF; "
      "`field` turns a scanned distance field or CT into a porous structure (seed 003); "
      "`conformal` grows a lattice layer that follows a surface (seed 004); `material` builds "
      "heterogeneous solids and slices them (seed 001); `render` draws a mesh to a PNG "
      "picture.\n",
      "tpmsfill"};
  app.set_version_flag("--version", "tpmsfill " TPMSFILL_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Run 'tpmsfill COMMAND --help' for a command's options. Exit codes: 0 ok, 1 mesh "
      "not valid (check), lattice failed validation (fill, slice) or mesh not repairable (repair), "
      "2 "
      "unreadable input or bad arguments, "
      "3 internal error.");

  Command check = add_check_command(app);
  Command fill = add_fill_command(app);
  Command repair = add_repair_command(app);
  Command decimate = add_decimate_command(app);
  Command field = add_field_command(app);
  Command conformal = add_conformal_command(app);
  Command slice = add_slice_command(app);
  Command render = add_render_command(app);
  Command material = add_material_command(app);
  Command serve = add_serve_command(app);

  // --progress on every command that takes --quiet, nested ones too (a command that shows
  // progress without --quiet adds it itself).
  auto add_progress = [](CLI::App* sub) {
    if (sub->get_option_no_throw("--quiet") && !sub->get_option_no_throw("--progress"))
      add_progress_flag(sub);
  };
  for (CLI::App* sub : app.get_subcommands({})) {
    add_progress(sub);
    for (CLI::App* nested : sub->get_subcommands({})) add_progress(nested);
  }

  set_command_line(argc, argv);  // for the reports' provenance
  // Arguments CLI11 cannot place are kept, not thrown, so that they get our own sentence
  // (with a did-you-mean) rather than CLI11's.
  app.allow_extras();
  for (CLI::App* sub : app.get_subcommands({})) {
    sub->allow_extras();
    for (CLI::App* nested : sub->get_subcommands({})) nested->allow_extras();
  }
  auto usage = [](const std::string& sentence) {
    std::fprintf(stderr, "tpmsfill: error: %s\n", sentence.c_str());
    return kBadInput;
  };
  if (std::string wrong = unknown_command(app, argc, argv); !wrong.empty()) return usage(wrong);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage(usage_error(app, e, argc, argv));
  }
  if (std::string extra = unplaced_arguments(app); !extra.empty()) return usage(extra);
  for (const CLI::App* sub : app.get_subcommands()) {
    if (std::string extra = unplaced_arguments(*sub); !extra.empty()) return usage(extra);
    for (const CLI::App* nested : sub->get_subcommands())
      if (std::string extra = unplaced_arguments(*nested); !extra.empty()) return usage(extra);
  }

  try {
    for (CLI::App* sub : app.get_subcommands())
      if (sub->get_name() == "check")
        return check();
      else if (sub->get_name() == "fill")
        return fill();
      else if (sub->get_name() == "repair")
        return repair();
      else if (sub->get_name() == "decimate")
        return decimate();
      else if (sub->get_name() == "field")
        return field();
      else if (sub->get_name() == "conformal")
        return conformal();
      else if (sub->get_name() == "slice")
        return slice();
      else if (sub->get_name() == "render")
        return render();
      else if (sub->get_name() == "material")
        return material();
      else if (sub->get_name() == "serve")
        return serve();
    return kBadInput;
  } catch (const tpmsfill::ValidationError& e) {
    std::fprintf(stderr, "tpmsfill: error: %s\n", tpmsfill::cli::printable(e.what()).c_str());
    return kNotValid;
  } catch (const tpmsfill::Error& e) {
    // Errors quote files (names, lib3mf's reasons, a recipe's keys): escapes shown, not run.
    std::fprintf(stderr, "tpmsfill: error: %s\n", tpmsfill::cli::printable(e.what()).c_str());
    return kBadInput;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "tpmsfill: error: out of memory\n");
    return kInternal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tpmsfill: internal error: %s\n",
                 tpmsfill::cli::printable(e.what()).c_str());
    return kInternal;
  }
}

}  // namespace

// Under mpirun every rank runs the command; an error on one stops them all.
int main(int argc, char** argv) {
  tpmsfill::cli::keep_freed_memory();
  // Ctrl-C, SIGTERM or a closed terminal during a write: the staged outputs are removed.
  tpmsfill::detail::remove_registered_paths_on_signals();
  // A job `tpmsfill serve` runs is cancelled by SIGTERM: the next progress report answers
  // false and the command stops there, writing nothing (the service kills one that never
  // reports after a grace period).
  if (tpmsfill::cli::service_progress_fd() >= 0)
    std::signal(SIGTERM, [](int) { tpmsfill::cli::cancel_requested() = true; });
  tpmsfill::cli::RanksSession session(argc, argv);
  const int code = run(argc, argv);
  if (code != 0 && tpmsfill::cli::ranks() > 1) tpmsfill::cli::abort_all(code);
  return code;
}
