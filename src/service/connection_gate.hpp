// The service's front door (issue 37): a connection is read to the end of its request headers
// by one event loop before a worker thread sees it. cpp-httplib gives each accepted connection
// a pool thread that waits on it byte by byte, its idle timeout restarting at every byte: 70
// clients sending a header byte a second held the pool and made /v1/health take 43 s.
#pragma once

#include <httplib.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace tpmsfill::service {

struct GateOptions {
  /// From a connection's first byte to the end of its request headers, at most (a total, not
  /// an idle time per byte).
  std::chrono::seconds header_deadline{10};
  /// A kept-alive connection waits this long for its next request.
  std::chrono::seconds keep_alive{5};
  /// Connections from one address waiting for their headers, at most: a new one pushes out
  /// the one that has waited longest (once it has waited `slow_after`), so a client that sends
  /// its request at once is always heard whatever slow ones hold.
  std::size_t per_address = 16;
  std::chrono::milliseconds slow_after{1000};  ///< a connection waiting longer is a slow one
  std::size_t waiting = 1024;                  ///< connections waiting for their headers, in all
  std::size_t header_bytes = 64 << 10;         ///< request line and headers, at most
  std::size_t workers = 64;  ///< threads that answer requests whose headers are in
};

/// An httplib::Server whose accepted connections go through the gate: routes, handlers and
/// settings are cpp-httplib's. Call close_gate() once listen_after_bind() has returned.
class GatedServer : public httplib::Server {
 public:
  explicit GatedServer(GateOptions options = {});
  ~GatedServer() override;

  /// Stops the event loop and the workers (requests being answered finish), closing every
  /// connection still waiting.
  void close_gate();

 private:
  struct Waiting {
    std::string bytes;  // what arrived so far
    std::string address;
    std::chrono::steady_clock::time_point since, deadline;
    int requests = 0;      // answered on this connection so far
    bool started = false;  // a byte of this request arrived
  };

  bool process_and_close_socket(socket_t sock) override;
  void admit(socket_t sock, Waiting w);
  void loop();
  void drop(socket_t sock);  // with mutex_ held
  void answer(socket_t sock, Waiting w);

  GateOptions options_;
  int epoll_ = -1, wake_ = -1;
  std::mutex mutex_;
  std::map<socket_t, Waiting> waiting_;
  bool closing_ = false;
  std::unique_ptr<httplib::ThreadPool> workers_;
  std::thread loop_;
};

}  // namespace tpmsfill::service
