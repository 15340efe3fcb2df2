// `tpmsfill serve`: the HTTP service (src/service/server.hpp, docs/service.md). This file only
// parses the flags and finds the token.
#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <tpmsfill/error.hpp>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/job_flags.hpp"
#include "cli/validators.hpp"
#include "service/server.hpp"

namespace tpmsfill::cli {
namespace {

namespace fs = std::filesystem;

struct ServeArgs {
  std::string listen = "127.0.0.1:8080";
  std::string data = "tpmsfill-data";
  int jobs = 1;
  std::string token_file;
  std::string max_upload = "512M";
  std::string memory;
  double keep_hours = 24;
  double job_timeout = 3600;
};

// The token from --token-file (its first line), or DATA/token, made with 128 random bits
// (readable by its owner only) when missing.
std::string find_token(const ServeArgs& a) {
  fs::path file = a.token_file;
  if (file.empty()) {
    file = fs::path(a.data) / "token";
    std::error_code ec;
    fs::create_directories(a.data, ec);
    if (!fs::exists(file)) {
      std::random_device device;
      char token[33];
      for (int i = 0; i < 4; ++i)
        std::snprintf(token + 8 * i, 9, "%08x", static_cast<unsigned>(device()));
      const mode_t old = umask(077);
      std::ofstream out(file);
      out << token << '\n';
      umask(old);
      if (!out) throw IoError(file.string() + ": cannot write the token");
    }
  }
  std::ifstream in(file);
  if (!in) throw IoError(file.string() + ": cannot read the token file");
  std::string token;
  std::getline(in, token);
  while (!token.empty() && (token.back() == '\r' || token.back() == ' ')) token.pop_back();
  if (token.size() < 16)
    throw InputError(file.string() + ": the token must be at least 16 characters long");
  std::error_code ec;
  const fs::perms mode = fs::status(file, ec).permissions();
  if (!ec && (mode & (fs::perms::group_read | fs::perms::others_read)) != fs::perms::none)
    std::fprintf(stderr,
                 "tpmsfill: warning: %s is readable by other users, who could then submit jobs "
                 "(chmod 600 it)\n",
                 file.string().c_str());
  std::printf("token: %s\n", fs::absolute(file).string().c_str());
  return token;
}

int run_serve(const ServeArgs& a) {
  // Jobs hold other people's parts: everything the service and its commands write is
  // readable by its own user only.
  umask(077);
  service::ServeOptions o;
  const std::size_t colon = a.listen.rfind(':');
  if (colon == std::string::npos || colon == 0)
    throw InputError("--listen: '" + a.listen + "' is not ADDRESS:PORT (e.g. 127.0.0.1:8080)");
  o.host = a.listen.substr(0, colon);
  try {
    std::size_t used = 0;
    o.port = std::stoi(a.listen.substr(colon + 1), &used);
    if (used != a.listen.size() - colon - 1 || o.port < 0 || o.port > 65535) throw 0;
  } catch (...) {
    throw InputError("--listen: the port in '" + a.listen + "' must be 0 to 65535");
  }
  o.data = a.data;
  o.jobs = a.jobs;
  o.max_upload = parse_bytes(a.max_upload, "--max-upload");
  if (!a.memory.empty()) o.memory = parse_bytes(a.memory);  // refused here, not in every job
  // Below the program's own allowance every fill and slice is refused and any other job soon
  // stopped; a bare number is likely a missing unit ("512" for 512M).
  if (o.memory > 0 && o.memory < service::kMemoryHeadroom) {
    const bool bare = a.memory.find_first_not_of("0123456789.") == std::string::npos;
    print_warnings(
        {"--memory " + a.memory + " gives each job " + std::to_string(o.memory) +
         " bytes: fill and slice jobs will be refused, other jobs stopped past " +
         std::to_string((o.memory + service::kMemoryHeadroom) >> 20) + " MB" +
         (bare ? " (a size without K, M or G is bytes: did you mean " + a.memory + "M?)" : "")});
  }
  o.keep = std::chrono::seconds(static_cast<long>(a.keep_hours * 3600));
  // Whole seconds, rounded up: 0.5 must not become 0, which is no limit at all.
  o.job_timeout = std::chrono::seconds(static_cast<long>(std::ceil(a.job_timeout)));
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) throw IoError("cannot find the tpmsfill program to run jobs with");
  o.program = std::string(self, static_cast<std::size_t>(n));
  o.token = find_token(a);
  return service::serve(o);
}

}  // namespace

Command add_serve_command(CLI::App& app) {
  auto args = std::make_shared<ServeArgs>();
  CLI::App* sub = app.add_subcommand(
      "serve",
      "Run the HTTP service and its web page: check, repair, fill, slice and material jobs from "
      "a browser or a script");
  sub->add_option("--listen", args->listen,
                  "ADDRESS:PORT to listen on (default 127.0.0.1:8080, this machine only; "
                  "0.0.0.0:8080 for the LAN; port 0: any free one, printed)");
  sub->add_option("--data", args->data,
                  "Folder for the queue, the jobs' inputs and results (default tpmsfill-data); "
                  "jobs there survive a restart");
  sub->add_option("--jobs", args->jobs, "Jobs run at once (default 1)")
      ->check(between(1, 64, "1 to 64"));
  sub->add_option("--token-file", args->token_file,
                  "File whose first line is the token clients send (Authorization: Bearer "
                  "TOKEN); default DATA/token, made when missing");
  sub->add_option("--max-upload", args->max_upload, "Largest mesh upload (default 512M)");
  sub->add_option("--memory", args->memory,
                  "Memory each job may use, e.g. 4G: fill and slice plan within it, and a job "
                  "past it (and 64M for the program itself) is stopped (default: half of "
                  "physical memory shared among the --jobs)");
  sub->add_option("--keep-hours", args->keep_hours,
                  "Finished jobs are deleted this many hours after they end (default 24)")
      ->check(between(0.01, 1e5, "0.01 to 100000"));
  sub->add_option("--job-timeout", args->job_timeout,
                  "Seconds a job may run; one past it is stopped and fails with that number "
                  "(default 3600; 0: no limit)")
      ->check(between(0, 1e7, "0 to 10000000"));
  sub->footer(
      "Endpoints, fields and status codes: docs/service.md. Stop with Ctrl-C (SIGINT) or "
      "SIGTERM; jobs that were running run again at the next start.\n"
      "Example:\n"
      "  tpmsfill serve --data /srv/tpmsfill --jobs 2\n"
      "  curl -H \"Authorization: Bearer $(cat /srv/tpmsfill/token)\" -F mesh=@part.stl "
      "http://127.0.0.1:8080/v1/check");
  return [args] { return run_serve(*args); };
}

}  // namespace tpmsfill::cli
