// `tpmsfill`: the command line. It parses arguments, calls the library and turns library
// exceptions into one line on stderr and an exit code; everything else lives in the library.
#include <cstdio>
#include <exception>
#include <tpmsfill/error.hpp>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"

int main(int argc, char** argv) {
  using namespace tpmsfill::cli;
  CLI::App app{
      "tpmsfill fills triangle meshes with TPMS lattices and proves that what it writes is a "
      "closed 2-manifold.\n"
      "Reads STL (ASCII or binary), OBJ, PLY and OFF, also gzip-compressed.\n",
      "tpmsfill"};
  app.set_version_flag("--version", "tpmsfill " TPMSFILL_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Run 'tpmsfill COMMAND --help' for a command's options. Exit codes: 0 ok, 1 mesh "
      "not valid (check), lattice failed validation (fill) or mesh not repairable (repair), 2 "
      "unreadable input or bad arguments, "
      "3 internal error.");

  Command check = add_check_command(app);
  Command fill = add_fill_command(app);
  Command repair = add_repair_command(app);

  set_command_line(argc, argv);  // for the reports' provenance
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version arrive here too, with exit code 0.
    int code = app.exit(e);
    return code == 0 ? kOk : kBadInput;
  }

  try {
    for (CLI::App* sub : app.get_subcommands())
      if (sub->get_name() == "check")
        return check();
      else if (sub->get_name() == "fill")
        return fill();
      else if (sub->get_name() == "repair")
        return repair();
    return kBadInput;
  } catch (const tpmsfill::ValidationError& e) {
    std::fprintf(stderr, "tpmsfill: error: %s\n", e.what());
    return kNotValid;
  } catch (const tpmsfill::Error& e) {
    std::fprintf(stderr, "tpmsfill: error: %s\n", e.what());
    return kBadInput;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "tpmsfill: error: out of memory\n");
    return kInternal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tpmsfill: internal error: %s\n", e.what());
    return kInternal;
  }
}
