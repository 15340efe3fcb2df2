#include "service/connection_gate.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>
#include <vector>

namespace tpmsfill::service {
namespace {

using Clock = std::chrono::steady_clock;

// The address and port of a socket's peer (remote) or its own end (local).
void address_of(socket_t sock, bool remote, std::string& ip, int& port) {
  sockaddr_storage a{};
  socklen_t length = sizeof a;
  ip.clear();
  port = 0;
  if ((remote ? getpeername : getsockname)(sock, reinterpret_cast<sockaddr*>(&a), &length) != 0)
    return;
  char text[INET6_ADDRSTRLEN] = {};
  if (a.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
    inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text);
    port = ntohs(v4->sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
    inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text);
    port = ntohs(v6->sin6_port);
  }
  ip = text;
}

// Whether `bytes` hold a whole request head: its line and headers, ended by an empty line.
bool head_complete(const std::string& bytes, std::size_t from) {
  const std::size_t start = from > 3 ? from - 3 : 0;
  return bytes.find("\n\r\n", start) != std::string::npos ||
         bytes.find("\n\n", start) != std::string::npos;
}

// What the gate answers itself, best effort (the socket may not take it), before closing.
void refuse(socket_t sock, const char* status) {
  const std::string text =
      std::string("HTTP/1.1 ") + status + "\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
  [[maybe_unused]] const ssize_t sent =
      send(sock, text.data(), text.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

// A connection for cpp-httplib's request processing: the bytes the gate read come first, then
// the socket, with the server's read and write timeouts per wait.
class GateStream : public httplib::Stream {
 public:
  GateStream(socket_t sock, std::string bytes, time_t read_seconds, time_t write_seconds)
      : sock_(sock),
        bytes_(std::move(bytes)),
        read_ms_(static_cast<int>(read_seconds * 1000)),
        write_ms_(static_cast<int>(write_seconds * 1000)) {}

  bool is_readable() const override { return at_ < bytes_.size() || ready(POLLIN, read_ms_); }
  bool is_writable() const override { return ready(POLLOUT, write_ms_); }

  ssize_t read(char* ptr, size_t size) override {
    if (at_ == bytes_.size()) {
      // cpp-httplib reads request lines a byte at a time: a buffer spares a call per byte.
      if (!ready(POLLIN, read_ms_)) return -1;
      bytes_.resize(16 << 10);
      at_ = 0;
      ssize_t n;
      do n = recv(sock_, bytes_.data(), bytes_.size(), 0);
      while (n < 0 && errno == EINTR);
      bytes_.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
      if (n <= 0) return n;
    }
    const std::size_t n = std::min(size, bytes_.size() - at_);
    std::memcpy(ptr, bytes_.data() + at_, n);
    at_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    if (!ready(POLLOUT, write_ms_)) return -1;
    ssize_t n;
    do n = send(sock_, ptr, size, MSG_NOSIGNAL);
    while (n < 0 && errno == EINTR);
    return n;
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    address_of(sock_, true, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    address_of(sock_, false, ip, port);
  }
  socket_t socket() const override { return sock_; }

  // Bytes read past the request just answered: the start of the next one.
  std::string leftover() const { return bytes_.substr(at_); }

 private:
  bool ready(short events, int ms) const {
    pollfd p{sock_, events, 0};
    int n;
    do n = poll(&p, 1, ms);
    while (n < 0 && errno == EINTR);
    return n > 0 && (p.revents & (events | POLLHUP)) != 0;
  }

  socket_t sock_;
  std::string bytes_;
  std::size_t at_ = 0;
  int read_ms_, write_ms_;
};

}  // namespace

GatedServer::GatedServer(GateOptions options) : options_(options) {
  // Accepting only hands the socket to the gate: two threads are plenty.
  new_task_queue = [] { return new httplib::ThreadPool(2); };
  epoll_ = epoll_create1(EPOLL_CLOEXEC);
  wake_ = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  epoll_event e{};
  e.events = EPOLLIN;
  e.data.fd = wake_;
  epoll_ctl(epoll_, EPOLL_CTL_ADD, wake_, &e);
  workers_ = std::make_unique<httplib::ThreadPool>(options_.workers);
  loop_ = std::thread([this] { loop(); });
}

GatedServer::~GatedServer() {
  close_gate();
  close(epoll_);
  close(wake_);
}

void GatedServer::close_gate() {
  {
    std::lock_guard lock(mutex_);
    if (closing_) return;
    closing_ = true;
    while (!waiting_.empty()) drop(waiting_.begin()->first);
  }
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_, &one, sizeof one);
  loop_.join();
  workers_->shutdown();
}

bool GatedServer::process_and_close_socket(socket_t sock) {
  Waiting w;
  std::string ip;
  int port = 0;
  address_of(sock, true, ip, port);
  w.address = ip;
  w.since = Clock::now();
  w.deadline = w.since + options_.header_deadline;
  admit(sock, std::move(w));
  return true;
}

void GatedServer::drop(socket_t sock) {
  epoll_ctl(epoll_, EPOLL_CTL_DEL, sock, nullptr);
  shutdown(sock, SHUT_RDWR);
  close(sock);
  waiting_.erase(sock);
}

void GatedServer::admit(socket_t sock, Waiting w) {
  std::lock_guard lock(mutex_);
  if (!closing_ && head_complete(w.bytes, 0)) {  // a pipelined request already whole
    workers_->enqueue([this, sock, w = std::move(w)]() mutable { answer(sock, std::move(w)); });
    return;
  }
  if (closing_) {
    shutdown(sock, SHUT_RDWR);
    close(sock);
    return;
  }
  // Over the caps, the connection that has waited longest goes, from this address first, once
  // it has waited a second: connections made together (50 checks at once) are not slow ones.
  // With none that old, a new connection past the total is the one refused.
  const auto now = Clock::now();
  const auto oldest = [&](bool same_address) {
    auto found = waiting_.end();
    std::size_t count = 0;
    for (auto it = waiting_.begin(); it != waiting_.end(); ++it) {
      if (same_address && it->second.address != w.address) continue;
      ++count;
      if (found == waiting_.end() || it->second.since < found->second.since) found = it;
    }
    return std::pair{found, count};
  };
  if (auto [it, count] = oldest(true);
      count >= options_.per_address && now - it->second.since >= options_.slow_after)
    drop(it->first);
  if (auto [it, count] = oldest(false); count >= options_.waiting) {
    if (now - it->second.since < options_.slow_after) {
      shutdown(sock, SHUT_RDWR);
      close(sock);
      return;
    }
    drop(it->first);
  }
  epoll_event e{};
  e.events = EPOLLIN | EPOLLRDHUP;
  e.data.fd = sock;
  if (epoll_ctl(epoll_, EPOLL_CTL_ADD, sock, &e) != 0) {
    shutdown(sock, SHUT_RDWR);
    close(sock);
    return;
  }
  waiting_[sock] = std::move(w);
  const std::uint64_t one = 1;  // the loop's next wake-up may now be sooner
  [[maybe_unused]] const ssize_t n = ::write(wake_, &one, sizeof one);
}

void GatedServer::loop() {
  std::vector<epoll_event> events(64);
  std::vector<char> buffer(16 << 10);
  for (;;) {
    int timeout_ms = 1000;
    {
      std::lock_guard lock(mutex_);
      if (closing_) return;
      const auto now = Clock::now();
      for (const auto& [sock, w] : waiting_) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(w.deadline - now).count();
        timeout_ms = static_cast<int>(std::clamp<long long>(left + 1, 0, timeout_ms));
      }
    }
    const int n = epoll_wait(epoll_, events.data(), static_cast<int>(events.size()), timeout_ms);
    std::vector<std::pair<socket_t, Waiting>> ready;
    {
      std::lock_guard lock(mutex_);
      if (closing_) return;
      const auto now = Clock::now();
      for (int k = 0; k < n; ++k) {
        const int fd = events[static_cast<std::size_t>(k)].data.fd;
        if (fd == wake_) {
          std::uint64_t count;
          while (::read(wake_, &count, sizeof count) > 0) {
          }
          continue;
        }
        const auto it = waiting_.find(fd);
        if (it == waiting_.end()) continue;
        Waiting& w = it->second;
        const std::size_t before = w.bytes.size();
        bool gone = false;
        for (;;) {
          const ssize_t got = recv(fd, buffer.data(), buffer.size(), MSG_DONTWAIT);
          if (got < 0 && errno == EINTR) continue;
          if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
          if (got <= 0) {
            gone = true;  // closed by the client, or broken
            break;
          }
          if (!w.started) {
            w.started = true;  // the request's headers are due from its first byte
            w.deadline = now + options_.header_deadline;
          }
          w.bytes.append(buffer.data(), static_cast<std::size_t>(got));
          if (w.bytes.size() > options_.header_bytes) break;
        }
        if (head_complete(w.bytes, before)) {
          epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
          ready.emplace_back(fd, std::move(w));
          waiting_.erase(it);
        } else if (w.bytes.size() > options_.header_bytes) {
          refuse(fd, "431 Request Header Fields Too Large");
          drop(fd);
        } else if (gone) {
          drop(fd);
        }
      }
      std::vector<socket_t> late;
      for (const auto& [sock, w] : waiting_)
        if (now >= w.deadline) late.push_back(sock);
      for (const socket_t sock : late) {
        if (waiting_[sock].started) refuse(sock, "408 Request Timeout");
        drop(sock);
      }
      for (auto& [sock, w] : ready)
        workers_->enqueue([this, sock, w = std::move(w)]() mutable { answer(sock, std::move(w)); });
    }
  }
}

void GatedServer::answer(socket_t sock, Waiting w) {
  GateStream stream(sock, std::move(w.bytes), read_timeout_sec_, write_timeout_sec_);
  ++w.requests;
  const bool last = w.requests >= static_cast<int>(keep_alive_max_count_) || !is_running();
  bool closed = false;
  const bool ok = process_request(stream, last, closed, nullptr);
  if (ok && !closed && !last) {
    // Kept alive: back to the gate for the next request's headers.
    w.bytes = stream.leftover();
    w.since = Clock::now();
    w.deadline = w.since + options_.keep_alive;
    w.started = !w.bytes.empty();
    if (w.started) w.deadline = w.since + options_.header_deadline;
    admit(sock, std::move(w));
    return;
  }
  shutdown(sock, SHUT_RDWR);
  close(sock);
}

}  // namespace tpmsfill::service
