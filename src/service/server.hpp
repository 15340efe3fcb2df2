// `tpmsfill serve` (issue 19): the HTTP service over the same commands as the command line.
// docs/service.md describes every endpoint, field and status code.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>

namespace tpmsfill::service {

struct ServeOptions {
  std::string host = "127.0.0.1";  ///< localhost unless asked otherwise
  int port = 8080;                 ///< 0: any free port (printed)
  std::filesystem::path data = "tpmsfill-data";
  int jobs = 1;                             ///< jobs run at once
  std::string token;                        ///< the bearer token every endpoint but health asks for
  std::uint64_t max_upload = 512ull << 20;  ///< bytes of a mesh part, at most
  /// Memory each job may use, in bytes: fill and slice plan within it (their --memory), and a
  /// job whose resident memory passes it by kMemoryHeadroom is stopped. 0: half of physical
  /// memory shared among the --jobs.
  std::uint64_t memory = 0;
  std::chrono::seconds keep{24 * 3600};    ///< finished jobs are deleted this long after
  std::chrono::seconds timeout{30};        ///< a client that sends or reads nothing this long
  std::chrono::seconds job_timeout{3600};  ///< a job running longer is stopped (0: never)
  std::filesystem::path program;           ///< the tpmsfill executable that runs the jobs
};

/// Beyond a job's budget, for the program itself (code, libraries, threads' stacks), which no
/// command's plan counts.
constexpr std::uint64_t kMemoryHeadroom = 64ull << 20;

/// The budget each job gets: options.memory, or half of physical memory over options.jobs.
std::uint64_t job_memory(const ServeOptions& options);

/// Serves until SIGINT or SIGTERM. Prints one line when listening ("listening on
/// http://HOST:PORT"). Jobs running when it stops are run again at the next start.
/// @throws IoError  the address cannot be bound, the data folder cannot be made
int serve(const ServeOptions& options);

}  // namespace tpmsfill::service
