// What a service job runs (issue 19): its kind (check, repair, fill, slice, material-*), the
// options a client sent, checked before the job is accepted, and the `tpmsfill` command line that
// runs it. The service runs every job as the command line would (same code, same guarantees), in a
// child process of its own: a crash or a runaway job cannot take the server with it.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace tpmsfill::service {

enum class JobKind { Check, Repair, Fill, Slice, MaterialFit, MaterialSlice, MaterialIso };

/// Every kind, in the order the API lists them.
const std::vector<JobKind>& job_kinds();
/// "check", "repair", "fill", "slice", "material-fit", "material-slice", "material-iso" (the
/// endpoints' names: POST /v1/NAME); nullopt for another name.
std::optional<JobKind> job_kind_from_name(const std::string& name);
const char* job_kind_name(JobKind kind);
/// "check, repair, ...": every kind's name, for sentences.
std::string job_kind_list();
/// Whether the kind's input is a fitted model (.tsm) rather than a mesh.
bool takes_model(JobKind kind);
/// Whether the command prints its report (--json) rather than writing it to paths.report.
bool report_on_stdout(JobKind kind);

/// A job's options, checked: what the command line gets besides IN and OUT, and the recipe
/// file's text for fill and slice (empty when none).
struct JobOptions {
  std::vector<std::string> flags;
  std::string recipe;
  std::string output_name;   ///< the result's file name in the job folder ("" for check)
  std::string content_type;  ///< the result's MIME type
};

/// What the command writes in the job folder: output_name, or for a ".zip" result the folder
/// of layers ("result") that the service then packs into it.
std::string command_output_name(const JobOptions& options);

/// Checks the `options` part of a request (a JSON object; "" means {}) against the kind's
/// keys (docs/service.md): unknown keys, wrong types, values out of range and recipes that
/// read_recipe() refuses are an InputError with the sentence the client gets in its 400.
JobOptions job_options(JobKind kind, const std::string& options_json);

/// The paths a job's command line names, all made by the service in the job's folder: nothing
/// of the client's reaches a path.
struct JobPaths {
  std::string input, output, recipe, report;
};

/// The command line (after the program name) that runs the job. fill and slice write their
/// report to paths.report; check and repair print it (--json) on stdout.
std::vector<std::string> job_command(JobKind kind, const JobOptions& options, const JobPaths& paths,
                                     std::uint64_t memory_budget);

}  // namespace tpmsfill::service
