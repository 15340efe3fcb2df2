#include "io/interrupt_cleanup.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <utility>

namespace tpmsfill::detail {
namespace {

// Fixed slots, so that the handler reads plain memory and allocates nothing. A slot is free
// (0), being written (1) or registered (2): the handler only reads registered ones.
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;

struct Slot {
  std::atomic<int> state{0};
  bool folder = false;
  char path[kPathBytes];
};

Slot g_slots[kSlots];

// The files in `folder` (one level: staged layers are flat), then the folder itself.
void remove_folder(const char* folder) noexcept {
  const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buffer[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
      if (n <= 0) break;
      for (long at = 0; at < n;) {
        // struct linux_dirent64: ino (8), off (8), reclen (2), type (1), name.
        unsigned short reclen;
        std::memcpy(&reclen, buffer + at + 16, sizeof reclen);
        const char* name = buffer + at + 19;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
        at += reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(folder);
}

void on_signal(int signal) {
  remove_registered_paths();
  // Then end as the signal would have: the default action, raised once this handler returns.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(signal, &dfl, nullptr);
  ::raise(signal);
}

}  // namespace

RemovedOnInterrupt::RemovedOnInterrupt(const std::filesystem::path& path, Kind kind) {
  const std::string& text = path.native();
  if (text.size() >= kPathBytes) return;
  for (int i = 0; i < kSlots; ++i) {
    int free = 0;
    if (!g_slots[i].state.compare_exchange_strong(free, 1)) continue;
    std::memcpy(g_slots[i].path, text.c_str(), text.size() + 1);
    g_slots[i].folder = kind == Kind::Folder;
    g_slots[i].state.store(2);
    slot_ = i;
    return;
  }
}

RemovedOnInterrupt& RemovedOnInterrupt::operator=(RemovedOnInterrupt&& other) noexcept {
  if (this != &other) {
    release();
    slot_ = std::exchange(other.slot_, -1);
  }
  return *this;
}

void RemovedOnInterrupt::release() {
  if (slot_ >= 0) g_slots[std::exchange(slot_, -1)].state.store(0);
}

void remove_registered_paths() noexcept {
  for (Slot& s : g_slots) {
    if (s.state.load() != 2) continue;
    if (s.folder)
      remove_folder(s.path);
    else
      ::unlink(s.path);
  }
}

void remove_registered_paths_on_signals() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  // A signal the process was started ignoring stays ignored: `nohup` (SIGHUP) and a shell's
  // background jobs (SIGINT) rely on it.
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction now {};
    if (::sigaction(signal, nullptr, &now) == 0 && now.sa_handler == SIG_IGN) continue;
    ::sigaction(signal, &action, nullptr);
  }
}

}  // namespace tpmsfill::detail
