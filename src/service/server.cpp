// `tpmsfill serve` (server.hpp): cpp-httplib (Debian's libcpp-httplib-dev) for HTTP, the job
// store for state, and one child process per running job.
#include "service/server.hpp"

#include <fcntl.h>
#include <httplib.h>
#include <poll.h>
#include <signal.h>
#include <strings.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>

#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <vector>

#include "io/file_bytes.hpp"
#include "io/formats.hpp"
#include "service/connection_gate.hpp"

#include "service/archive.hpp"
#include "service/job_spec.hpp"
#include "service/job_store.hpp"
#include "service/web_assets.hpp"

namespace tpmsfill::service {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr std::size_t kMaxOptionsBytes = 1 << 20;
// A cancelled job that never reports progress (check) is killed after this long.
constexpr auto kCancelGrace = std::chrono::seconds(5);

void answer(httplib::Response& res, int status, const Json& body) {
  res.status = status;
  res.set_content(body.dump(2) + "\n", "application/json");
}

void refuse(httplib::Response& res, int status, const std::string& sentence) {
  answer(res, status, {{"error", sentence}});
}

// Equal in time whatever the first difference: the token is not leaked a byte at a time.
bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;  // the length is no secret worth keeping
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The extension an upload is kept under, lower case, or "" when the kind's command cannot read
// a file of that name: a mesh's (the readers' own format_from_extension decides), a glTF
// scene's (one file: what it names beside itself is only looked for in its job's folder), or,
// for the kinds that take one, a fitted model's.
std::string input_extension(JobKind kind, const std::string& name) {
  if (takes_model(kind)) return detail::lower_extension(fs::path(name)) == ".tsm" ? ".tsm" : "";
  // Of the scenes, glTF alone: mutated FBX files make assimp 5.2 free memory twice (found by
  // mutating assimp-testmodels' files under AddressSanitizer), which no upload may reach.
  if (const std::string ext = detail::lower_extension(fs::path(name));
      ext == ".glb" || ext == ".gltf")
    return ext;
  if (format_from_extension(name) == MeshFormat::Auto) return "";
  const bool gzip = is_gzip_name(name);
  return detail::lower_extension(gzip ? fs::path(name).stem() : fs::path(name)) +
         (gzip ? ".gz" : "");
}

// A process's resident memory in bytes (0 when it is gone).
std::uint64_t resident_memory(pid_t pid) {
  std::ifstream statm("/proc/" + std::to_string(pid) + "/statm");
  std::uint64_t size = 0, resident = 0;
  if (!(statm >> size >> resident)) return 0;
  return resident * static_cast<std::uint64_t>(sysconf(_SC_PAGE_SIZE));
}

// SIGINT and SIGTERM are taken by one thread (sigwait), which stops the server.
sigset_t stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

// The job-running half: worker threads take queued jobs and run each as a child process.
class Runner {
 public:
  Runner(JobStore& store, const ServeOptions& options) : store_(store), options_(options) {
    for (int i = 0; i < options.jobs; ++i) workers_.emplace_back([this] { work(); });
  }
  ~Runner() { stop(); }

  void wake() { wake_.notify_all(); }

  void stop() {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
      stopping_ = true;
      // Jobs stopped here stay "running" on disk and run again at the next start.
      for (const auto& [id, pid] : children_) kill(pid, SIGKILL);
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
    for (std::thread& t : cancellers_) t.join();
  }

  // Cancels a running job through its progress (SIGTERM: the command's progress callback
  // answers false and it stops at its next report, writing nothing), then kills it if it
  // has not stopped after kCancelGrace.
  void cancel(const std::string& id) {
    pid_t pid = 0;
    {
      std::lock_guard lock(mutex_);
      const auto it = children_.find(id);
      if (it == children_.end()) return;
      pid = it->second;
    }
    kill(pid, SIGTERM);
    std::lock_guard lock(mutex_);
    cancellers_.emplace_back([this, id, pid] {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, kCancelGrace, [&] {
        const auto it = children_.find(id);
        return stopping_ || it == children_.end() || it->second != pid;
      });
      const auto it = children_.find(id);
      if (it != children_.end() && it->second == pid) kill(pid, SIGKILL);
    });
  }

 private:
  void work() {
    for (;;) {
      std::optional<JobRecord> job;
      {
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, std::chrono::seconds(1),
                       [&] { return stopping_ || store_.queued() > 0; });
        if (stopping_) return;
      }
      job = store_.start_next();
      if (job) run(*job);
    }
  }

  void run(const JobRecord& job) {
    const fs::path dir = store_.folder(job.id);
    // The command runs in the job's folder with names relative to it: its report and the
    // files' provenance name "input.stl", not where the server keeps its data.
    const std::string dir_path = dir.string();
    const JobPaths paths{job.input_name, command_output_name(job.options), "recipe.json",
                         "report.json"};
    std::vector<std::string> args = {options_.program.string()};
    for (std::string& a : job_command(job.kind, job.options, paths, job_memory(options_)))
      args.push_back(std::move(a));
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // The environment with the progress pipe's number, made before fork (no allocation after).
    std::vector<std::string> env_strings = {"TPMSFILL_PROGRESS_FD=3"};
    for (char** e = environ; *e; ++e)
      if (std::strncmp(*e, "TPMSFILL_PROGRESS_FD=", 21) != 0) env_strings.emplace_back(*e);
    std::vector<char*> envp;
    for (std::string& e : env_strings) envp.push_back(e.data());
    envp.push_back(nullptr);

    const sigset_t stop_set = stop_signals();
    int pipe_fds[2];
    if (pipe2(pipe_fds, O_CLOEXEC) != 0) {
      finish_failed(job.id, "the server could not start the job (no pipe)");
      return;
    }
    pid_t pid = 0;
    {
      std::lock_guard lock(mutex_);
      if (stopping_) {
        close(pipe_fds[0]);
        close(pipe_fds[1]);
        return;
      }
      // Only async-signal-safe calls between fork and exec; everything is prepared above.
      pid = fork();
      if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);  // a job never outlives the server
        // The server blocks SIGINT and SIGTERM for its sigwait thread, and a child inherits
        // the mask: the job must see SIGTERM (its cancel).
        sigprocmask(SIG_UNBLOCK, &stop_set, nullptr);
        if (chdir(dir_path.c_str()) != 0) _exit(127);
        const int out = open("stdout.txt", O_WRONLY | O_CREAT | O_TRUNC, 0600);
        const int err = open("stderr.txt", O_WRONLY | O_CREAT | O_TRUNC, 0600);
        const int devnull = open("/dev/null", O_RDONLY);
        if (out < 0 || err < 0 || devnull < 0) _exit(127);
        dup2(devnull, 0);
        dup2(out, 1);
        dup2(err, 2);
        if (pipe_fds[1] == 3)
          fcntl(3, F_SETFD, 0);  // keep it open across exec
        else
          dup2(pipe_fds[1], 3);  // the copy is open across exec
        execve(argv[0], argv.data(), envp.data());
        _exit(127);
      }
      if (pid > 0) children_[job.id] = pid;
    }
    close(pipe_fds[1]);
    // A DELETE between start_next() and the fork found no child to signal.
    if (pid > 0) {
      const std::optional<JobRecord> now = store_.get(job.id);
      if (now && now->cancel_asked) cancel(job.id);
    }
    if (pid < 0) {
      close(pipe_fds[0]);
      finish_failed(job.id, "the server could not start the job (fork failed)");
      return;
    }
    Ending ending = read_progress(job.id, pipe_fds[0], pid);
    close(pipe_fds[0]);
    int status = 0;
    rusage usage{};
    while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    ending.peak_memory = static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // Linux: KiB
    {
      std::lock_guard lock(mutex_);
      children_.erase(job.id);
      // Killed because the server stops: the record stays "running", so the job runs again
      // at the next start (JobStore's constructor).
      if (stopping_) return;
    }
    wake_.notify_all();
    sweep_temporaries(dir);  // a command killed for memory or a cancel leaves its staged files
    finish(job, status, dir, ending);
  }

  // Why the service stopped a command itself: the memory it had reached, or its time ran out.
  struct Ending {
    std::uint64_t over_memory = 0;
    bool timed_out = false;
    std::uint64_t peak_memory = 0;  ///< the command's peak resident bytes (wait4's rusage)
  };

  // Progress lines from the command ("stage<TAB>fraction<TAB>overall"), until it exits. Its
  // resident memory is read every 100 ms: past the budget and headroom it is killed, as it is
  // past --job-timeout.
  Ending read_progress(const std::string& id, int fd, pid_t pid) {
    constexpr auto kEvery = std::chrono::milliseconds(100);
    const std::uint64_t limit = job_memory(options_) + kMemoryHeadroom;
    const auto started = std::chrono::steady_clock::now();
    auto next_reading = started;
    std::string pending;
    char buffer[4096];
    for (;;) {
      pollfd ready{fd, POLLIN, 0};
      const int polled = poll(&ready, 1, static_cast<int>(kEvery.count()));
      if (polled < 0 && errno == EINTR) continue;
      // Read on the clock, not per progress line (a fill reports thousands).
      if (const auto now = std::chrono::steady_clock::now(); now >= next_reading) {
        next_reading = now + kEvery;
        if (const std::uint64_t rss = resident_memory(pid); rss > limit) {
          kill(pid, SIGKILL);
          return {.over_memory = rss};
        }
        if (options_.job_timeout.count() > 0 && now - started > options_.job_timeout) {
          kill(pid, SIGKILL);
          return {.timed_out = true};
        }
      }
      if (polled == 0) continue;
      const ssize_t n = read(fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return {};
      pending.append(buffer, static_cast<std::size_t>(n));
      std::size_t end;
      std::string last;
      while ((end = pending.find('\n')) != std::string::npos) {
        last = pending.substr(0, end);
        pending.erase(0, end + 1);
      }
      if (last.empty()) continue;
      const std::size_t tab1 = last.find('\t'), tab2 = last.rfind('\t');
      if (tab1 == std::string::npos) continue;
      const std::string stage = last.substr(0, tab1);
      const double overall = tab2 > tab1 ? std::atof(last.c_str() + tab2 + 1) : -1;
      store_.update(
          id,
          [&](JobRecord& r) {
            r.stage = stage;
            if (overall >= 0) r.progress = std::max(r.progress, std::min(overall, 1.0));
          },
          false);
    }
  }

  void finish(const JobRecord& job, int status, const fs::path& dir, const Ending& ending) {
    const std::uint64_t over_memory = ending.over_memory;
    const std::string err = read_text(dir / "stderr.txt");
    std::string sentence, warnings;
    std::istringstream lines(err);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("tpmsfill: error: ", 0) == 0) sentence = line.substr(17);
      if (line.rfind("tpmsfill: warning: ", 0) == 0) warnings += line.substr(19) + "\n";
    }
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    Json report;
    try {
      const std::string text = report_on_stdout(job.kind) ? read_text(dir / "stdout.txt")
                                                          : read_text(dir / "report.json");
      if (!text.empty()) report = Json::parse(text);
    } catch (const std::exception&) {
      report = nullptr;
    }
    // check's exit 1 is its verdict (not valid), not a failure.
    bool ok = code == 0 || (job.kind == JobKind::Check && code == 1 && !report.is_null());
    // A folder of layers becomes the one file the result is.
    const std::string written = command_output_name(job.options);
    if (ok && !over_memory && written != job.options.output_name) {
      try {
        zip_folder(dir / written, dir / job.options.output_name);
        std::error_code ec;
        fs::remove_all(dir / written, ec);
      } catch (const Error& e) {
        ok = false;
        sentence = e.what();
      }
    }
    store_.update(
        job.id,
        [&](JobRecord& r) {
          r.exit_code = code;
          r.warnings = warnings;
          r.peak_memory = ending.peak_memory;
          if (r.cancel_asked) {
            r.state = JobState::Cancelled;
            r.error = sentence.empty() ? "cancelled (killed: it did not stop within " +
                                             std::to_string(kCancelGrace.count()) + " s)"
                                       : sentence;
            std::error_code ec;
            if (!r.options.output_name.empty()) {
              fs::remove_all(dir / command_output_name(r.options), ec);
              fs::remove(dir / r.options.output_name, ec);
            }
          } else if (ok) {
            r.state = JobState::Done;
            r.progress = 1;
            r.report = report;
          } else {
            r.state = JobState::Failed;
            r.report = report;
            r.error =
                ending.timed_out ? "stopped: it ran past the service's " +
                                       std::to_string(options_.job_timeout.count()) +
                                       " s a job (serve --job-timeout)"
                : over_memory > 0
                    ? "stopped: it used " + std::to_string(over_memory >> 20) +
                          " MB, past the service's " + std::to_string(job_memory(options_) >> 20) +
                          " MB a job (serve --memory) and " +
                          std::to_string(kMemoryHeadroom >> 20) + " MB for the program itself"
                : !sentence.empty()   ? sentence
                : WIFSIGNALED(status) ? "the job stopped on signal " +
                                            std::to_string(WTERMSIG(status)) + " (out of memory?)"
                                      : "the job ended with exit code " + std::to_string(code);
          }
        },
        true);
  }

  void finish_failed(const std::string& id, const std::string& sentence) {
    store_.update(
        id,
        [&](JobRecord& r) {
          r.state = JobState::Failed;
          r.error = sentence;
        },
        true);
  }

  JobStore& store_;
  const ServeOptions& options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::map<std::string, pid_t> children_;
  std::vector<std::thread> workers_;
  std::vector<std::thread> cancellers_;  // one per cancel; joined at stop()
};

// A POST /v1/KIND request's parts: the mesh streamed to a file under the cap, the options
// kept in memory.
struct Upload {
  fs::path file;
  std::string extension;
  std::string options;
  std::uint64_t bytes = 0;
  bool has_mesh = false;
  std::string problem;  // a sentence for a 400/413, or ""
  int status = 400;
  ~Upload() {
    std::error_code ec;
    if (!file.empty()) fs::remove(file, ec);
  }
};

constexpr const char* kNotMultipart = "the request body is not multipart/form-data";

bool read_upload(const httplib::ContentReader& reader, const fs::path& uploads,
                 std::uint64_t max_upload, JobKind kind, Upload& up) {
  std::ofstream mesh;
  std::string part;  // the part being read
  static std::atomic<std::uint64_t> counter{0};
  const bool read = reader(
      [&](const httplib::MultipartFormData& header) {
        part = header.name;
        if (part == "mesh") {
          if (up.has_mesh) {
            up.problem = "send one mesh part";
            return false;
          }
          up.has_mesh = true;
          up.extension = input_extension(kind, header.filename);
          if (up.extension.empty()) {
            up.problem = std::string(takes_model(kind)
                                         ? "mesh: send a fitted model, a .tsm file from "
                                           "material-fit"
                                         : "mesh: the file name must end in .stl, .obj, .ply, "
                                           ".off (each also .gz), .3mf, or a glTF scene's (.glb, "
                                           "or .gltf with its buffers inside)") +
                         " (it was '" + header.filename + "')";
            return false;
          }
          up.file = uploads / ("upload-" + std::to_string(getpid()) + "-" +
                               std::to_string(counter++) + ".part");
          mesh.open(up.file, std::ios::binary | std::ios::trunc);
          if (!mesh) {
            up.problem = "the server cannot store the upload";
            up.status = 500;
            return false;
          }
        } else if (part != "options") {
          up.problem = "unknown part '" + part + "' (send 'mesh' and, optionally, 'options')";
          return false;
        }
        return true;
      },
      [&](const char* data, std::size_t length) {
        if (part == "mesh") {
          up.bytes += length;
          if (up.bytes > max_upload) {
            up.problem = "mesh: over the upload limit of " + std::to_string(max_upload) + " bytes";
            up.status = 413;
            return false;
          }
          mesh.write(data, static_cast<std::streamsize>(length));
          return static_cast<bool>(mesh);
        }
        up.options.append(data, length);
        if (up.options.size() > kMaxOptionsBytes) {
          up.problem = "options: over 1 MB";
          up.status = 413;
          return false;
        }
        return true;
      });
  mesh.close();
  if (!read && up.problem.empty()) up.problem = kNotMultipart;
  if (up.problem.empty() && !up.has_mesh) up.problem = "no 'mesh' part: send the mesh file";
  return up.problem.empty();
}

// What the route handlers share; each handler keeps a copy (references only).
struct Routes {
  const ServeOptions& options;
  JobStore& store;
  Runner& runner;
  const std::atomic<bool>& stopping;  // set when the server stops: event streams end

  bool authorised(const httplib::Request& req, httplib::Response& res) const {
    const std::string header = req.get_header_value("Authorization");
    // The scheme is case-insensitive (RFC 7235 §2.1): "bearer" is "Bearer".
    if (header.size() > 7 && strncasecmp(header.c_str(), "Bearer ", 7) == 0 &&
        same_secret(header.substr(7), options.token))
      return true;
    res.set_header("WWW-Authenticate", "Bearer");
    refuse(res, 401, "send the service's token: Authorization: Bearer TOKEN");
    return false;
  }

  // The job named by the path's first group, or a 404 (then nullopt).
  std::optional<JobRecord> job_or_404(const httplib::Request& req, httplib::Response& res) const {
    // Ids are validated before any lookup: nothing else ever names a job's folder.
    std::optional<JobRecord> job;
    if (is_job_id(req.matches[1])) job = store.get(req.matches[1]);
    if (!job)
      refuse(res, 404,
             "no job with this id (finished jobs are kept for " +
                 std::to_string(options.keep.count() / 3600) + " hours)");
    return job;
  }
};

std::vector<std::string> kind_names() {
  std::vector<std::string> names;
  for (JobKind kind : job_kinds()) names.emplace_back(job_kind_name(kind));
  return names;
}

void add_page_routes(httplib::Server& server) {
  // The page and its two files: public (they hold no data; every call they make asks for the
  // token), same-origin only, never cached stale.
  server.Get(R"(/|/index\.html|/app\.js|/style\.css)", [](const httplib::Request& req,
                                                          httplib::Response& res) {
    const std::optional<WebAsset> asset = web_asset(req.path);
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_header("Referrer-Policy", "no-referrer");
    res.set_header("Content-Security-Policy",
                   "default-src 'self'; img-src 'self' blob: data:; "
                   "object-src 'none'; frame-ancestors 'none'; base-uri 'none'");
    // Sent as stored (gzipped at build time when the client takes gzip): through a
    // content provider, which cpp-httplib does not compress again.
    const bool gzip = req.get_header_value("Accept-Encoding").find("gzip") != std::string::npos;
    const std::string_view bytes = gzip ? asset->gzipped : asset->body;
    if (gzip) res.set_header("Content-Encoding", "gzip");
    res.set_header("Vary", "Accept-Encoding");
    res.set_content_provider(
        bytes.size(), asset->content_type,
        [bytes](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
          return sink.write(bytes.data() + offset, std::min(length, bytes.size() - offset));
        });
  });
}

// Health, version, and POST /v1/KIND: a job accepted onto the queue.
void add_submit_routes(httplib::Server& server, const Routes& r) {
  server.Get("/v1/health", [r](const httplib::Request&, httplib::Response& res) {
    answer(res, 200, {{"status", "ok"}, {"queued", r.store.queued()}});
  });
  server.Get("/v1/version", [r](const httplib::Request& req, httplib::Response& res) {
    if (!r.authorised(req, res)) return;
    answer(res, 200,
           {{"version", TPMSFILL_VERSION},
            {"kinds", kind_names()},
            {"page", web_page_bundled()},
            {"max_upload_bytes", r.options.max_upload}});
  });
  server.Post(R"(/v1/([^/]+))", [r](const httplib::Request& req, httplib::Response& res,
                                    const httplib::ContentReader& reader) {
    if (!r.authorised(req, res)) return;
    const std::optional<JobKind> known = job_kind_from_name(req.matches[1]);
    if (!known)
      return refuse(
          res, 404,
          "no job kind '" + std::string(req.matches[1]) + "' (kinds: " + job_kind_list() + ")");
    const JobKind kind = *known;
    if (!req.is_multipart_form_data())
      return refuse(res, 400, "send multipart/form-data with a 'mesh' file part");
    Upload up;
    if (!read_upload(reader, r.store.uploads_dir(), r.options.max_upload, kind, up)) {
      // A body past the payload cap stops the reader before any part is seen (curl sends its
      // headers, waits for 100 Continue, and cpp-httplib refuses the length): the limit, 413.
      const std::string length = req.get_header_value("Content-Length");
      if (up.problem == kNotMultipart && !length.empty() &&
          std::strtoull(length.c_str(), nullptr, 10) > r.options.max_upload)
        return refuse(res, 413,
                      "the request is over the upload limit of " +
                          std::to_string(r.options.max_upload) + " bytes");
      return refuse(res, up.status, up.problem);
    }
    JobOptions accepted;
    try {
      accepted = job_options(kind, up.options);
    } catch (const Error& e) {
      return refuse(res, 400, e.what());
    }
    const std::string id = r.store.add(kind, accepted, up.file, up.extension);
    up.file.clear();  // moved into the job
    r.runner.wake();
    res.set_header("Location", "/v1/jobs/" + id);
    answer(res, 202, {{"id", id}, {"state", "queued"}});
  });
}

// GET /v1/jobs/ID (with long polling) and its event stream.
void add_progress_routes(httplib::Server& server, const Routes& r) {
  // Long polling: ?wait=S answers when the job's state or stage changes, or after S seconds
  // (at most 30).
  server.Get(R"(/v1/jobs/([^/]+))", [r](const httplib::Request& req, httplib::Response& res) {
    if (!r.authorised(req, res)) return;
    std::optional<JobRecord> job = r.job_or_404(req, res);
    if (!job) return;
    double wait = req.has_param("wait") ? std::atof(req.get_param_value("wait").c_str()) : 0;
    wait = std::clamp(wait, 0.0, 30.0);
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait);
    const JobState state = job->state;
    const std::string stage = job->stage;
    while (!job_ended(state) && !r.stopping && std::chrono::steady_clock::now() < until &&
           job->state == state && job->stage == stage) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      job = r.store.get(job->id);
      if (!job) return refuse(res, 404, "the job was deleted");
    }
    answer(res, 200, record_json(*job));
  });
  // Server-sent events: the job's record whenever it changes (state, stage, progress), a
  // comment every 15 s so proxies keep the stream open, and the end of the stream once the job
  // has ended. Each stream holds one of the pool's threads, as a long poll does.
  server.Get(
      R"(/v1/jobs/([^/]+)/events)", [r](const httplib::Request& req, httplib::Response& res) {
        if (!r.authorised(req, res)) return;
        std::optional<JobRecord> job = r.job_or_404(req, res);
        if (!job) return;
        res.set_header("Cache-Control", "no-cache");
        auto sent = std::make_shared<std::string>();  // the last record sent
        res.set_chunked_content_provider(
            "text/event-stream", [r, id = job->id, sent](std::size_t, httplib::DataSink& sink) {
              const auto keep_alive = std::chrono::steady_clock::now() + std::chrono::seconds(15);
              while (!r.stopping) {
                const std::optional<JobRecord> now = r.store.get(id);
                if (!now) {  // expired or deleted under us
                  sink.done();
                  return true;
                }
                std::string record = record_json(*now).dump();
                if (record != *sent) {
                  const std::string event = "data: " + record + "\n\n";
                  *sent = std::move(record);
                  if (!sink.write(event.data(), event.size())) return false;
                  if (job_ended(now->state)) sink.done();
                  return true;
                }
                if (std::chrono::steady_clock::now() >= keep_alive) {
                  static constexpr char comment[] = ": still here\n\n";
                  return sink.write(comment, sizeof comment - 1);
                }
                if (!sink.is_writable()) return false;
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
              }
              return false;
            });
      });
}

// GET /v1/jobs/ID/result and DELETE /v1/jobs/ID (cancel).
void add_result_routes(httplib::Server& server, const Routes& r) {
  server.Get(
      R"(/v1/jobs/([^/]+)/result)", [r](const httplib::Request& req, httplib::Response& res) {
        if (!r.authorised(req, res)) return;
        std::optional<JobRecord> job = r.job_or_404(req, res);
        if (!job) return;
        if (job->state != JobState::Done)
          return refuse(
              res, 409,
              std::string("the job is ") + job_state_name(job->state) + ", there is no result");
        if (job->options.output_name.empty())
          return refuse(res, 404, "a check job has no result file: its report is the answer");
        const fs::path file = r.store.folder(job->id) / job->options.output_name;
        auto stream = std::make_shared<std::ifstream>(file, std::ios::binary);
        std::error_code ec;
        const std::uint64_t size = fs::file_size(file, ec);
        if (!*stream || ec) return refuse(res, 410, "the result file is gone");
        res.set_header("Content-Disposition",
                       "attachment; filename=\"" + job->options.output_name + "\"");
        res.set_content_provider(
            size, job->options.content_type,
            [stream](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
              std::vector<char> buffer(std::min<std::size_t>(length, 1 << 16));
              stream->seekg(static_cast<std::streamoff>(offset));
              stream->read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
              const auto got = stream->gcount();
              if (got <= 0) return false;
              return sink.write(buffer.data(), static_cast<std::size_t>(got));
            });
      });
  server.Delete(R"(/v1/jobs/([^/]+))", [r](const httplib::Request& req, httplib::Response& res) {
    if (!r.authorised(req, res)) return;
    std::optional<JobRecord> job = r.job_or_404(req, res);
    if (!job) return;
    bool running = false, finished = false;
    r.store.update(
        job->id,
        [&](JobRecord& record) {
          if (record.state == JobState::Queued) {
            record.state = JobState::Cancelled;
          } else if (record.state == JobState::Running) {
            record.cancel_asked = true;
            running = true;
          } else {
            finished = true;
          }
        },
        true);
    if (finished)
      return refuse(res, 409,
                    std::string("the job has already ended (") + job_state_name(job->state) + ")");
    if (running) r.runner.cancel(job->id);
    answer(res, 202, {{"id", job->id}, {"state", running ? "cancelling" : "cancelled"}});
  });
}

}  // namespace

std::uint64_t job_memory(const ServeOptions& options) {
  return options.memory > 0 ? options.memory
                            : default_memory_budget() / static_cast<std::uint64_t>(options.jobs);
}

int serve(const ServeOptions& options) {
  if (options.token.size() < 16) throw InputError("the token must be at least 16 characters long");
  const sigset_t signals = stop_signals();
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // inherited by every thread made below
  JobStore store(options.data, options.keep);
  std::atomic<bool> stopping = false;
  Runner runner(store, options);
  // Requests are short (an upload to disk, a record read) but long polls hold a worker up to
  // 30 s: 64 workers, more than cpp-httplib's 8; none of them waits for a slow client's
  // headers (connection_gate.hpp).
  GatedServer server(GateOptions{.workers = 64});
  server.set_read_timeout(options.timeout.count(), 0);
  server.set_write_timeout(options.timeout.count(), 0);
  server.set_keep_alive_timeout(5);
  // cpp-httplib 0.11 listens with a backlog of 5: in a burst, connections past it wait in
  // SYN retransmits for tens of seconds (50 checks at once: one in 50 timed out after 60 s).
  // The socket is kept here and listened on again with the system's largest backlog.
  int listening_socket = -1;
  server.set_socket_options([&listening_socket](socket_t sock) {
    const int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);  // cpp-httplib's default
    listening_socket = sock;
  });
  server.set_payload_max_length(options.max_upload + kMaxOptionsBytes + (64 << 10));

  // What cpp-httplib answers itself (no route, a body past the payload cap, a request it
  // cannot parse) gets a sentence too, not an empty body.
  server.set_error_handler([&options](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a route's refusal
    if (res.status == 404)
      refuse(res, 404, "no endpoint " + req.method + " " + req.path + " (docs/service.md)");
    else if (res.status == 413)
      refuse(res, 413,
             "the request is over the upload limit of " + std::to_string(options.max_upload) +
                 " bytes");
    else
      refuse(res, res.status,
             "the request could not be read (HTTP " + std::to_string(res.status) + ")");
  });
  const Routes routes{options, store, runner, stopping};
  add_page_routes(server);
  add_submit_routes(server, routes);
  add_progress_routes(server, routes);
  add_result_routes(server, routes);

  int port = options.port;
  if (port == 0) {
    port = server.bind_to_any_port(options.host.c_str());
    if (port < 0) throw IoError(options.host + ": cannot listen there");
  } else if (!server.bind_to_port(options.host.c_str(), port)) {
    throw IoError(options.host + ":" + std::to_string(port) +
                  ": cannot listen there (in use? a name that does not resolve?)");
  }
  std::printf("listening on http://%s:%d\n", options.host.c_str(), port);
  std::printf("the page: http://%s:%d/ (paste the token into its token field)\n",
              options.host.c_str(), port);
  if (listening_socket >= 0) ::listen(listening_socket, SOMAXCONN);
  std::fflush(stdout);

  std::atomic<bool> listen_returned = false;
  std::thread stopper([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    stopping = true;  // event streams end, so the pool's threads can be joined
    // A signal right after "listening on" may come before listen_after_bind() runs, when
    // stop() does nothing and the server would then listen for ever: wait until it runs.
    while (!server.is_running() && !listen_returned)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    server.stop();
  });
  // Finished jobs past --keep, checked every minute until the server stops.
  std::mutex expiry_mutex;
  std::condition_variable expiry_wake;
  bool done = false;
  std::thread expirer([&] {
    std::unique_lock lock(expiry_mutex);
    while (!expiry_wake.wait_for(lock, std::chrono::minutes(1), [&] { return done; }))
      store.expire();
  });
  server.listen_after_bind();
  listen_returned = true;
  server.close_gate();
  {
    std::lock_guard lock(expiry_mutex);
    done = true;
  }
  expiry_wake.notify_all();
  runner.stop();
  // The stopper waits for a signal that may not come (the server stopped another way).
  pthread_kill(stopper.native_handle(), SIGTERM);
  stopper.join();
  expirer.join();
  return 0;
}

}  // namespace tpmsfill::service
