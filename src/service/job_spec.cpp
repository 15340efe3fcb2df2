// Job options checked against each kind's keys, and the command line that runs the job.
#include "service/job_spec.hpp"

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/units.hpp>

namespace tpmsfill::service {
namespace {

using Json = nlohmann::json;

// How one key of a kind's options becomes a flag.
enum class Value {
  Positive,    // a number > 0: "--flag VALUE"
  Fraction,    // a number in [0, 1): "--flag VALUE"
  Count,       // an integer in [0, 1e6]: "--flag VALUE"
  Number,      // any finite number: "--flag VALUE"
  Units,       // mm, cm, m, in, um: "--flag VALUE"
  FlagIfTrue,  // true: "--flag"
  FlagIfFalse  // false: "--flag" (a default-on behaviour turned off)
};

struct Key {
  const char* name;
  const char* flag;
  Value value;
};

const std::vector<Key>& keys_of(JobKind kind) {
  static const std::vector<Key> check = {
      {"units", "--units", Value::Units},
      {"self_intersections", "--no-self-intersections", Value::FlagIfFalse},
      {"max_examples", "--max-examples", Value::Count}};
  static const std::vector<Key> repair = {
      {"units", "--units", Value::Units},
      {"wrap", "--no-wrap", Value::FlagIfFalse},
      {"alpha", "--alpha", Value::Positive},
      {"offset", "--offset", Value::Positive},
      {"tolerance", "--tolerance", Value::Positive},
      {"accept_deviation", "--accept-deviation", Value::FlagIfTrue},
      {"fill_holes", "--no-fill-holes", Value::FlagIfFalse},
      {"min_component", "--min-component", Value::Fraction}};
  static const std::vector<Key> slice = {{"layer", "--layer", Value::Positive},
                                         {"start", "--start", Value::Number},
                                         {"pixel", "--pixel", Value::Positive}};
  static const std::vector<Key> none;
  switch (kind) {
    case JobKind::Check:
      return check;
    case JobKind::Repair:
      return repair;
    case JobKind::Slice:
      return slice;
    case JobKind::Fill:
      return none;
  }
  return none;
}

std::string key_list(JobKind kind) {
  std::string out;
  for (const Key& k : keys_of(kind)) out += std::string(out.empty() ? "" : ", ") + k.name;
  if (kind == JobKind::Fill) out = "those of a recipe (docs/recipes.md)";
  if (kind == JobKind::Slice) out += ", format, recipe";
  return out;
}

std::string number_text(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

// The flags one key adds, or an InputError naming the key and what it takes.
void add_flags(const Key& key, const Json& value, std::vector<std::string>& flags) {
  const std::string where = std::string("options: ") + key.name + ": ";
  switch (key.value) {
    case Value::FlagIfTrue:
    case Value::FlagIfFalse: {
      if (!value.is_boolean()) throw InputError(where + "must be true or false");
      if (value.get<bool>() == (key.value == Value::FlagIfTrue)) flags.push_back(key.flag);
      return;
    }
    case Value::Units: {
      if (!value.is_string()) throw InputError(where + "must be a unit name (mm, cm, m, in, um)");
      units_from_name(value.get<std::string>());  // its own sentence for an unknown name
      flags.insert(flags.end(), {key.flag, value.get<std::string>()});
      return;
    }
    default:
      break;
  }
  if (!value.is_number()) throw InputError(where + "must be a number");
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw InputError(where + "must be finite");
  if (key.value == Value::Positive && !(x > 0)) throw InputError(where + "must be above 0");
  if (key.value == Value::Fraction && !(x >= 0 && x < 1))
    throw InputError(where + "must be at least 0 and below 1");
  if (key.value == Value::Count && !(x >= 0 && x <= 1e6 && x == std::floor(x)))
    throw InputError(where + "must be a whole number from 0 to 1000000");
  flags.insert(flags.end(),
               {key.flag,
                key.value == Value::Count ? std::to_string(static_cast<long>(x)) : number_text(x)});
}

// The first key naming a file (a porous structure's "field", a grading's "volume") anywhere in
// a recipe, or "": the command would read that path on the server's disk.
std::string file_key(const Json& j) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      if ((key == "field" || key == "volume") && value.is_string()) return key;
      if (std::string inner = file_key(value); !inner.empty()) return key + "." + inner;
    }
  } else if (j.is_array()) {
    for (const Json& value : j)
      if (std::string inner = file_key(value); !inner.empty()) return inner;
  }
  return "";
}

// A recipe checked by the reader fill and slice use, kept as the text they will read.
std::string checked_recipe(const Json& recipe) {
  if (!recipe.is_object()) throw InputError("options: the recipe must be a JSON object");
  if (const std::string key = file_key(recipe); !key.empty())
    throw InputError("options: " + key +
                     ": the service reads no files named in a recipe (only the uploaded mesh)");
  const std::string text = recipe.dump(2);
  read_recipe(text, "options");  // throws the sentence the command line would print
  return text;
}

}  // namespace

std::optional<JobKind> job_kind_from_name(const std::string& name) {
  for (JobKind kind : {JobKind::Check, JobKind::Repair, JobKind::Fill, JobKind::Slice})
    if (name == job_kind_name(kind)) return kind;
  return std::nullopt;
}

const char* job_kind_name(JobKind kind) {
  switch (kind) {
    case JobKind::Check:
      return "check";
    case JobKind::Repair:
      return "repair";
    case JobKind::Fill:
      return "fill";
    case JobKind::Slice:
      return "slice";
  }
  return "?";
}

JobOptions job_options(JobKind kind, const std::string& options_json) {
  Json options = Json::object();
  if (!options_json.empty()) {
    try {
      options = Json::parse(options_json);
    } catch (const Json::parse_error& e) {
      throw InputError(std::string("options: not valid JSON (byte ") + std::to_string(e.byte) +
                       ")");
    }
  }
  if (!options.is_object()) throw InputError("options: must be a JSON object");
  JobOptions out;
  if (kind == JobKind::Fill) {
    out.recipe = checked_recipe(options);
    out.output_name = "result.stl";
    out.content_type = "model/stl";
    return out;
  }
  std::string format = "cli";
  for (const auto& [name, value] : options.items()) {
    if (kind == JobKind::Slice && name == "recipe") {
      out.recipe = checked_recipe(value);
      continue;
    }
    if (kind == JobKind::Slice && name == "format") {
      if (!value.is_string() || (value != "cli" && value != "svg"))
        throw InputError("options: format: must be \"cli\" or \"svg\"");
      format = value.get<std::string>();
      continue;
    }
    const auto& keys = keys_of(kind);
    const auto key =
        std::find_if(keys.begin(), keys.end(), [&](const Key& k) { return name == k.name; });
    if (key == keys.end())
      throw InputError("options: unknown key '" + name + "' for " + job_kind_name(kind) +
                       " (known: " + key_list(kind) + ")");
    add_flags(*key, value, out.flags);
  }
  switch (kind) {
    case JobKind::Check:
      out.flags.push_back("--json");
      break;
    case JobKind::Repair:
      out.flags.push_back("--json");
      out.output_name = "result.stl";
      out.content_type = "model/stl";
      break;
    case JobKind::Slice:
      if (!options.contains("layer"))
        throw InputError("options: layer: the layer thickness in mm is required");
      out.output_name = "result." + format;
      out.content_type = format == "svg" ? "image/svg+xml" : "text/plain";
      break;
    case JobKind::Fill:
      break;
  }
  return out;
}

std::vector<std::string> job_command(JobKind kind, const JobOptions& options, const JobPaths& paths,
                                     const std::string& memory_budget) {
  std::vector<std::string> command = {job_kind_name(kind), paths.input};
  if (!options.output_name.empty()) command.push_back(paths.output);
  command.insert(command.end(), options.flags.begin(), options.flags.end());
  if (!options.recipe.empty()) command.insert(command.end(), {"--recipe", paths.recipe});
  if (kind == JobKind::Fill || kind == JobKind::Slice) {
    command.insert(command.end(), {"--report", paths.report});
    if (!memory_budget.empty()) command.insert(command.end(), {"--memory", memory_budget});
  }
  return command;
}

}  // namespace tpmsfill::service
