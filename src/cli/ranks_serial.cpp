// One process: what the commands see without MPI.
#include <cstdlib>
#include <stdexcept>

#include "cli/ranks.hpp"

namespace tpmsfill::cli {

RanksSession::RanksSession(int&, char**&) {}
RanksSession::~RanksSession() = default;
int rank() {
  return 0;
}
int ranks() {
  return 1;
}
bool any(bool mine) {
  return mine;
}
void send(int, const std::string&) {
  throw std::logic_error("send: there is one rank");
}
std::string receive(int) {
  throw std::logic_error("receive: there is one rank");
}
std::string broadcast(const std::string& bytes) {
  return bytes;
}
void abort_all(int code) {
  std::exit(code);
}

}  // namespace tpmsfill::cli
