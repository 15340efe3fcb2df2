// The service's jobs on disk (job_store.hpp).
#include "service/job_store.hpp"

#include <algorithm>
#include <fstream>
#include <random>
#include <sstream>
#include <tpmsfill/error.hpp>

namespace tpmsfill::service {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::int64_t now_seconds() {
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// 128 random bits as hex: ids cannot be guessed from one another.
std::string random_id() {
  std::random_device device;
  std::string id;
  for (int i = 0; i < 4; ++i) {
    char part[9];
    std::snprintf(part, sizeof part, "%08x", static_cast<unsigned>(device()));
    id += part;
  }
  return id;
}

std::optional<JobState> state_from_name(const std::string& name) {
  for (JobState s :
       {JobState::Queued, JobState::Running, JobState::Done, JobState::Failed, JobState::Cancelled})
    if (name == job_state_name(s)) return s;
  return std::nullopt;
}

// Everything needed to rerun the job, and what it came to.
Json stored_json(const JobRecord& job) {
  Json j = record_json(job);
  j["input_name"] = job.input_name;
  j["flags"] = job.options.flags;
  j["recipe"] = job.options.recipe;
  j["output_name"] = job.options.output_name;
  j["content_type"] = job.options.content_type;
  j["attempts"] = job.attempts;
  j["exit_code"] = job.exit_code;
  return j;
}

JobRecord record_from_json(const Json& j) {
  JobRecord job;
  job.id = j.at("id").get<std::string>();
  job.kind = job_kind_from_name(j.at("kind").get<std::string>()).value();
  job.state = state_from_name(j.at("state").get<std::string>()).value();
  job.input_name = j.at("input_name").get<std::string>();
  job.options.flags = j.at("flags").get<std::vector<std::string>>();
  job.options.recipe = j.at("recipe").get<std::string>();
  job.options.output_name = j.at("output_name").get<std::string>();
  job.options.content_type = j.at("content_type").get<std::string>();
  job.attempts = j.at("attempts").get<int>();
  job.exit_code = j.at("exit_code").get<int>();
  job.stage = j.value("stage", "");
  job.progress = j.value("progress", 0.0);
  job.error = j.value("error", "");
  job.warnings = j.value("warnings", "");
  if (j.contains("report")) job.report = j["report"];
  job.created = j.at("created").get<std::int64_t>();
  job.finished = j.value("finished", std::int64_t{0});
  job.peak_memory = j.value("peak_memory_bytes", std::uint64_t{0});
  return job;
}

}  // namespace

bool job_ended(JobState state) {
  return state != JobState::Queued && state != JobState::Running;
}

const char* job_state_name(JobState state) {
  switch (state) {
    case JobState::Queued:
      return "queued";
    case JobState::Running:
      return "running";
    case JobState::Done:
      return "done";
    case JobState::Failed:
      return "failed";
    case JobState::Cancelled:
      return "cancelled";
  }
  return "?";
}

Json record_json(const JobRecord& job) {
  Json j;
  j["id"] = job.id;
  j["kind"] = job_kind_name(job.kind);
  j["state"] = job_state_name(job.state);
  j["stage"] = job.stage;
  j["progress"] = job.progress;
  j["created"] = job.created;
  if (job.finished > 0) j["finished"] = job.finished;
  if (job.peak_memory > 0) j["peak_memory_bytes"] = job.peak_memory;
  if (!job.error.empty()) j["error"] = job.error;
  if (!job.warnings.empty()) j["warnings"] = job.warnings;
  if (!job.report.is_null()) j["report"] = job.report;
  if (job.state == JobState::Done && !job.options.output_name.empty())
    j["result"] = "/v1/jobs/" + job.id + "/result";
  return j;
}

bool is_job_id(const std::string& id) {
  return id.size() == 32 && std::all_of(id.begin(), id.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

void sweep_temporaries(const fs::path& folder) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    const bool staged = name.starts_with('.') && (name.find(".staged-") != std::string::npos ||
                                                  name.find(".tmp-") != std::string::npos);
    const bool layers =
        name.find(".tmp-") != std::string::npos || name.find(".old-") != std::string::npos;
    if (staged || layers) fs::remove_all(entry.path(), ec);
  }
}

JobStore::JobStore(fs::path data, std::chrono::seconds keep) : data_(std::move(data)), keep_(keep) {
  std::error_code ec;
  fs::create_directories(data_ / "jobs", ec);
  fs::create_directories(data_ / "uploads", ec);
  if (!fs::is_directory(data_ / "jobs") || !fs::is_directory(data_ / "uploads"))
    throw IoError(data_.string() + ": cannot make the data folder");
  // Uploads that never became jobs (the server stopped mid-request).
  for (const auto& entry : fs::directory_iterator(data_ / "uploads")) fs::remove(entry.path(), ec);
  std::vector<JobRecord> found;
  for (const auto& entry : fs::directory_iterator(data_ / "jobs")) {
    const std::string id = entry.path().filename().string();
    if (!is_job_id(id)) continue;
    sweep_temporaries(entry.path());  // a command killed mid-write (or with the server)
    std::ifstream in(entry.path() / "job.json");
    JobRecord job;
    try {
      job = record_from_json(Json::parse(in));
    } catch (const std::exception&) {
      // A folder whose record was never completed: accepted requests are answered only
      // after job.json is in place, so no client holds this id.
      fs::remove_all(entry.path(), ec);
      continue;
    }
    if (job.state == JobState::Running) {
      job.stage.clear();
      job.progress = 0;
      if (job.attempts >= 2) {
        job.state = JobState::Failed;
        job.error = "the server stopped twice while this job ran; it was not run again";
        job.finished = now_seconds();
      } else {
        job.state = JobState::Queued;  // interrupted once: it runs again from the start
      }
      save(job);
    }
    found.push_back(std::move(job));
  }
  std::sort(found.begin(), found.end(), [](const JobRecord& a, const JobRecord& b) {
    return std::tie(a.created, a.id) < std::tie(b.created, b.id);
  });
  for (JobRecord& job : found) {
    if (job.state == JobState::Queued) queue_.push_back(job.id);
    jobs_[job.id] = std::move(job);
  }
  expire();
}

void JobStore::save(const JobRecord& job) const {
  const fs::path file = folder(job.id) / "job.json";
  const fs::path temporary = folder(job.id) / "job.json.tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << stored_json(job).dump(2) << '\n';
    out.flush();
    if (!out) throw IoError(temporary.string() + ": cannot write the job's record");
  }
  fs::rename(temporary, file);
}

std::string JobStore::add(JobKind kind, const JobOptions& options, const fs::path& upload,
                          const std::string& extension) {
  JobRecord job;
  job.id = random_id();
  job.kind = kind;
  job.options = options;
  job.input_name = "input" + extension;
  job.created = now_seconds();
  const fs::path dir = folder(job.id);
  fs::create_directories(dir);
  fs::rename(upload, dir / job.input_name);
  if (!options.recipe.empty()) {
    std::ofstream out(dir / "recipe.json");
    out << options.recipe;
    if (!out) throw IoError((dir / "recipe.json").string() + ": cannot write");
  }
  save(job);  // last: a folder without job.json is not a job (see the constructor)
  std::lock_guard lock(mutex_);
  queue_.push_back(job.id);
  jobs_[job.id] = job;
  return job.id;
}

std::optional<JobRecord> JobStore::get(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return std::nullopt;
  return it->second;
}

std::optional<JobRecord> JobStore::start_next() {
  std::lock_guard lock(mutex_);
  while (!queue_.empty()) {
    const std::string id = queue_.front();
    queue_.erase(queue_.begin());
    auto it = jobs_.find(id);
    if (it == jobs_.end() || it->second.state != JobState::Queued) continue;  // cancelled
    it->second.state = JobState::Running;
    it->second.attempts += 1;
    save(it->second);
    return it->second;
  }
  return std::nullopt;
}

void JobStore::update(const std::string& id, const std::function<void(JobRecord&)>& change,
                      bool save_it) {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return;
  change(it->second);
  if (job_ended(it->second.state) && it->second.finished == 0) it->second.finished = now_seconds();
  if (save_it) save(it->second);
}

std::size_t JobStore::expire() {
  std::lock_guard lock(mutex_);
  const std::int64_t cutoff = now_seconds() - keep_.count();
  std::size_t removed = 0;
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    if (job_ended(it->second.state) && it->second.finished < cutoff) {
      std::error_code ec;
      fs::remove_all(folder(it->first), ec);
      it = jobs_.erase(it);
      ++removed;
    } else {
      ++it;
    }
  }
  return removed;
}

std::size_t JobStore::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

}  // namespace tpmsfill::service
