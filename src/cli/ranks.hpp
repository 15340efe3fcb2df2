// The processes one run of the tool is split among: one, or mpirun's ranks when the tool is
// built with -DTPMSFILL_MPI=ON (ranks_mpi.cpp; ranks_serial.cpp otherwise). Commands split
// their z range by rank; rank 0 gathers, writes and prints. Only bytes cross this seam, so
// the library never sees MPI.
#pragma once

#include <cstdint>
#include <string>

namespace tpmsfill::cli {

/// Starts MPI when the tool has it (before anything else reads argv) and stops it at exit.
class RanksSession {
 public:
  RanksSession(int& argc, char**& argv);
  ~RanksSession();
  RanksSession(const RanksSession&) = delete;
  RanksSession& operator=(const RanksSession&) = delete;
};

int rank();           ///< this process's rank, 0 .. ranks() − 1
int ranks();          ///< how many processes run this command (1 without MPI)
bool any(bool mine);  ///< whether any rank's `mine` is true (every rank calls it)
void send(int to, const std::string& bytes);
std::string receive(int from);
/// `bytes` as rank 0 has them, on every rank.
std::string broadcast(const std::string& bytes);
/// Stops every rank after an error on this one (no-op with one rank).
[[noreturn]] void abort_all(int code);

/// This rank's share [first, end) of `count` items, in rank order, as even as can be.
inline void share(std::uint64_t count, std::uint64_t& first, std::uint64_t& end) {
  const auto r = static_cast<std::uint64_t>(rank()), n = static_cast<std::uint64_t>(ranks());
  first = count * r / n;
  end = count * (r + 1) / n;
}

}  // namespace tpmsfill::cli
