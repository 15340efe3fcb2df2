// The service's jobs on disk (issue 19): every accepted job is a folder under DATA/jobs named
// by its id, holding its input, options, state and outputs, so that a restart loses nothing.
// Every state change is written to a temporary file and renamed over job.json (atomic on one
// file system); the store keeps the same records in memory for answering quickly.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "service/job_spec.hpp"

namespace tpmsfill::service {

enum class JobState { Queued, Running, Done, Failed, Cancelled };
const char* job_state_name(JobState state);
/// Done, failed or cancelled: the state will not change again.
bool job_ended(JobState state);

struct JobRecord {
  std::string id;
  JobKind kind = JobKind::Check;
  JobState state = JobState::Queued;
  std::string input_name;  ///< the input's file name in the folder ("input.stl", ...)
  JobOptions options;
  std::string stage;      ///< the stage running now ("" before the first)
  double progress = 0;    ///< overall fraction in [0, 1]
  int attempts = 0;       ///< times a run started (a restart mid-run reruns it once)
  int exit_code = -1;     ///< the command's, when it ended
  std::string error;      ///< the sentence, when failed
  std::string warnings;   ///< the command's warnings (stderr lines), when it ended
  nlohmann::json report;  ///< the command's report, when done
  std::int64_t created = 0, finished = 0;  ///< seconds since the epoch
  /// The command's peak resident memory (bytes, its rusage), once it ended: what a job of
  /// this size needs, to size serve --memory by.
  std::uint64_t peak_memory = 0;
  bool cancel_asked = false;
};

nlohmann::json record_json(const JobRecord& job);  ///< what GET /v1/jobs/{id} answers

/// True for the ids the store makes: 32 lowercase hex digits. Anything else is no job (and
/// never reaches a path).
bool is_job_id(const std::string& id);

/// Removes what a command killed mid-write leaves in a job's folder: its staged files
/// (".NAME.staged-PID-N", ".NAME.tmp-XXXXXX") and folders of layers ("NAME.tmp-PID",
/// "NAME.old-PID"). Run when a job's command ends and on every job at the server's start.
void sweep_temporaries(const std::filesystem::path& folder);

class JobStore {
 public:
  /// Opens DATA (made if missing) and reads back every job: queued ones queue again; one that
  /// was running when the server stopped queues again once, and fails with the reason after a
  /// second interruption; finished ones older than `keep` are deleted.
  JobStore(std::filesystem::path data, std::chrono::seconds keep);

  /// A new job's folder with its input moved in (from `upload`, a file in uploads_dir()) and
  /// its record saved, queued. Returns its id.
  std::string add(JobKind kind, const JobOptions& options, const std::filesystem::path& upload,
                  const std::string& extension);

  std::optional<JobRecord> get(const std::string& id) const;
  std::filesystem::path folder(const std::string& id) const { return data_ / "jobs" / id; }
  std::filesystem::path uploads_dir() const { return data_ / "uploads"; }

  /// The oldest queued job, marked running (attempts + 1), or nullopt.
  std::optional<JobRecord> start_next();
  /// Changes a job under the lock and saves it when `save` (progress is not saved: a restart
  /// reruns the job anyway).
  void update(const std::string& id, const std::function<void(JobRecord&)>& change, bool save);
  /// Deletes finished jobs older than `keep`; returns how many.
  std::size_t expire();
  std::size_t queued() const;

 private:
  void save(const JobRecord& job) const;
  std::filesystem::path data_;
  std::chrono::seconds keep_;
  mutable std::mutex mutex_;
  std::map<std::string, JobRecord> jobs_;
  std::vector<std::string> queue_;  // ids in the order they were accepted
};

}  // namespace tpmsfill::service
