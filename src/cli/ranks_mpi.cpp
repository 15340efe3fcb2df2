// mpirun's ranks, through MPI_COMM_WORLD. Messages are sent in pieces of at most 1 GiB, since
// MPI counts in int. Started without a launcher (no mpirun, srun or PMI in the environment),
// the tool is one process and never touches MPI, so plain runs cost nothing more.
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>

#include "cli/ranks.hpp"

namespace tpmsfill::cli {
namespace {

constexpr std::uint64_t kPiece = 1ull << 30;

bool launched = false;  // MPI is initialised: the tool was started by a launcher

bool started_by_launcher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

void send_all(const char* data, std::uint64_t size, int to) {
  for (std::uint64_t at = 0; at < size; at += kPiece)
    MPI_Send(data + at, static_cast<int>(std::min(kPiece, size - at)), MPI_BYTE, to, 1,
             MPI_COMM_WORLD);
}

void receive_all(char* data, std::uint64_t size, int from) {
  for (std::uint64_t at = 0; at < size; at += kPiece)
    MPI_Recv(data + at, static_cast<int>(std::min(kPiece, size - at)), MPI_BYTE, from, 1,
             MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

}  // namespace

RanksSession::RanksSession(int& argc, char**& argv) {
  if (!started_by_launcher()) return;
  MPI_Init(&argc, &argv);
  launched = true;
}

RanksSession::~RanksSession() {
  if (launched) MPI_Finalize();
}

int rank() {
  int r = 0;
  if (launched) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int ranks() {
  int n = 1;
  if (launched) MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

bool any(bool mine) {
  if (!launched) return mine;
  int in = mine ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return out != 0;
}

void send(int to, const std::string& bytes) {
  const std::uint64_t size = bytes.size();
  MPI_Send(&size, 1, MPI_UINT64_T, to, 0, MPI_COMM_WORLD);
  send_all(bytes.data(), size, to);
}

std::string receive(int from) {
  std::uint64_t size = 0;
  MPI_Recv(&size, 1, MPI_UINT64_T, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::string bytes(size, '\0');
  receive_all(bytes.data(), size, from);
  return bytes;
}

std::string broadcast(const std::string& bytes) {
  if (!launched) return bytes;
  std::uint64_t size = bytes.size();
  MPI_Bcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  std::string out = rank() == 0 ? bytes : std::string(size, '\0');
  for (std::uint64_t at = 0; at < size; at += kPiece)
    MPI_Bcast(out.data() + at, static_cast<int>(std::min(kPiece, size - at)), MPI_BYTE, 0,
              MPI_COMM_WORLD);
  return out;
}

void abort_all(int code) {
  if (launched) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

}  // namespace tpmsfill::cli
