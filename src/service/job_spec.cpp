// Job options checked against each kind's keys, and the command line that runs the job.
#include "service/job_spec.hpp"

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/layer_files.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/units.hpp>

#include "core/json_depth.hpp"

namespace tpmsfill::service {
namespace {

using Json = nlohmann::json;

// How one key of a kind's options becomes a flag.
enum class Value {
  Positive,     // a number > 0: "--flag VALUE"
  Fraction,     // a number in [0, 1): "--flag VALUE"
  Count,        // an integer in [0, 1e6]: "--flag VALUE"
  Number,       // any finite number: "--flag VALUE"
  Units,        // mm, cm, m, in, um: "--flag VALUE"
  FlagIfTrue,   // true: "--flag"
  FlagIfFalse,  // false: "--flag" (a default-on behaviour turned off)
  Point,        // [x, y, z]: "--flag X Y Z"
  Numbers,      // [a, b, ...], at least one: "--flag A B ..."
  Material,     // ["point", x, y, z], ["geodesic", depth], ["x"|"y"|"z"|"radial", a, b]
  Format        // a layer format's name (layer_files.hpp): "--flag NAME"
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
                                         {"format", "--format", Value::Format},
                                         {"pixel", "--pixel", Value::Positive}};
  static const std::vector<Key> material_fit = {
      {"units", "--units", Value::Units},
      {"cell", "--cell", Value::Positive},
      {"feature_angle", "--feature-angle", Value::Positive},
      {"material", "--material", Value::Material},
      {"up", "--up", Value::Point},
      {"max_tets_per_cell", "--max-tets-per-cell", Value::Count},
      {"max_level", "--max-level", Value::Count},
      {"uniform", "--uniform", Value::Count},
      {"step", "--step", Value::Positive},
      {"refinements", "--refinements", Value::Count},
      {"refine_share", "--refine-share", Value::Number},
      {"rs_change", "--rs-change", Value::Number},
      {"max_iterations", "--max-iterations", Value::Count}};
  static const std::vector<Key> material_slice = {
      {"layer", "--layer", Value::Positive},     {"start", "--start", Value::Number},
      {"format", "--format", Value::Format},     {"pixel", "--pixel", Value::Positive},
      {"colour", "--colour", Value::FlagIfTrue}, {"bins", "--bins", Value::Count},
      {"tau", "--tau", Value::Positive},         {"initial_level", "--initial-level", Value::Count},
      {"max_level", "--max-level", Value::Count}};
  static const std::vector<Key> material_iso = {{"values", "--values", Value::Numbers},
                                                {"tau", "--tau", Value::Positive},
                                                {"initial_level", "--initial-level", Value::Count},
                                                {"max_level", "--max-level", Value::Count}};
  static const std::vector<Key> none;
  switch (kind) {
    case JobKind::Check:
      return check;
    case JobKind::Repair:
      return repair;
    case JobKind::Slice:
      return slice;
    case JobKind::MaterialFit:
      return material_fit;
    case JobKind::MaterialSlice:
      return material_slice;
    case JobKind::MaterialIso:
      return material_iso;
    case JobKind::Fill:
      return none;
  }
  return none;
}

// "a, b, c".
template <class Range, class Name>
std::string comma_list(const Range& items, Name name) {
  std::string out;
  for (const auto& item : items) out += std::string(out.empty() ? "" : ", ") + name(item);
  return out;
}

std::string key_list(JobKind kind) {
  std::string out = comma_list(keys_of(kind), [](const Key& k) { return k.name; });
  if (kind == JobKind::Fill) out = "those of a recipe (docs/recipes.md)";
  if (kind == JobKind::Slice) out += ", recipe";
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
    case Value::Format: {
      const char* formats = "must be cli, cli-binary, svg, svg-layers or png";
      if (!value.is_string()) throw InputError(where + formats);
      try {
        layer_format_from_name(value.get<std::string>());
      } catch (const InputError&) {
        throw InputError(where + formats);
      }
      flags.insert(flags.end(), {key.flag, value.get<std::string>()});
      return;
    }
    case Value::Point:
    case Value::Numbers:
    case Value::Material: {
      const char* shape = key.value == Value::Point     ? "must be [x, y, z] in mm"
                          : key.value == Value::Numbers ? "must be a list of numbers"
                                                        : "must be [\"point\", x, y, z], "
                                                          "[\"geodesic\", depth] or "
                                                          "[\"x\"|\"y\"|\"z\"|\"radial\", a, b]";
      if (!value.is_array() || value.empty()) throw InputError(where + shape);
      std::vector<std::string> words;
      for (const Json& item : value) {
        if (key.value == Value::Material && words.empty()) {
          if (!item.is_string()) throw InputError(where + shape);
          const std::string kind = item.get<std::string>();
          if (kind == "ct")
            throw InputError(where + "a CT volume is a file; the service reads only the upload");
          const std::size_t wanted = kind == "point"      ? 4
                                     : kind == "geodesic" ? 2
                                     : kind == "x" || kind == "y" || kind == "z" || kind == "radial"
                                         ? 3
                                         : 0;
          if (wanted == 0 || value.size() != wanted) throw InputError(where + shape);
          words.push_back(kind);
          continue;
        }
        if (!item.is_number() || !std::isfinite(item.get<double>()))
          throw InputError(where + shape);
        words.push_back(number_text(item.get<double>()));
      }
      if (key.value == Value::Point && words.size() != 3) throw InputError(where + shape);
      flags.push_back(key.flag);
      flags.insert(flags.end(), words.begin(), words.end());
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

const std::vector<JobKind>& job_kinds() {
  static const std::vector<JobKind> kinds = {
      JobKind::Check,       JobKind::Repair,        JobKind::Fill,       JobKind::Slice,
      JobKind::MaterialFit, JobKind::MaterialSlice, JobKind::MaterialIso};
  return kinds;
}

std::string job_kind_list() {
  return comma_list(job_kinds(), job_kind_name);
}

std::optional<JobKind> job_kind_from_name(const std::string& name) {
  for (JobKind kind : job_kinds())
    if (name == job_kind_name(kind)) return kind;
  return std::nullopt;
}

bool takes_model(JobKind kind) {
  return kind == JobKind::MaterialSlice || kind == JobKind::MaterialIso;
}

bool report_on_stdout(JobKind kind) {
  return kind != JobKind::Fill && kind != JobKind::Slice;
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
    case JobKind::MaterialFit:
      return "material-fit";
    case JobKind::MaterialSlice:
      return "material-slice";
    case JobKind::MaterialIso:
      return "material-iso";
  }
  return "?";
}

JobOptions job_options(JobKind kind, const std::string& options_json) {
  Json options = Json::object();
  if (!options_json.empty()) {
    if (const auto byte = detail::json_too_deep(options_json))
      throw InputError("options: JSON nested more than " + std::to_string(detail::kMaxJsonDepth) +
                       " levels deep (byte " + std::to_string(*byte) + "; the limit)");
    try {
      options = Json::parse(options_json);
    } catch (const Json::parse_error& e) {
      throw InputError(std::string("options: not valid JSON (byte ") + std::to_string(e.byte) +
                       ")");
    } catch (const Json::exception&) {
      // A number past a double's range (found by fuzzing): nlohmann's out_of_range, no byte.
      throw InputError("options: not valid JSON (a number out of range)");
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
  for (const auto& [name, value] : options.items()) {
    if (kind == JobKind::Slice && name == "recipe") {
      out.recipe = checked_recipe(value);
      continue;
    }
    const auto& keys = keys_of(kind);
    // A structured binding is not captured (clang 14, which builds the fuzzers): by name.
    const std::string& asked = name;
    const auto key =
        std::find_if(keys.begin(), keys.end(), [&](const Key& k) { return asked == k.name; });
    if (key == keys.end())
      throw InputError("options: unknown key '" + name + "' for " + job_kind_name(kind) +
                       " (known: " + key_list(kind) + ")");
    add_flags(*key, value, out.flags);
  }
  const auto required = [&](const char* key, const char* what) {
    if (!options.contains(key)) throw InputError(std::string("options: ") + key + ": " + what);
  };
  // Layers (slice, material-slice): a file, or a folder of layers sent as one zip (archive.hpp).
  const auto layers = [&] {
    required("layer", "the layer thickness in mm is required");
    const std::string format = options.value("format", "cli");
    if (options.contains("pixel") && format != "png")
      throw InputError(
          "options: pixel: sets the PNG masks' pixel size; it needs \"format\": \"png\"");
    if (!options.contains("format")) out.flags.insert(out.flags.end(), {"--format", format});
    if (writes_folder(layer_format_from_name(format))) {
      out.output_name = "result.zip";
      out.content_type = "application/zip";
    } else {
      out.output_name = format == "svg" ? "result.svg" : "result.cli";
      out.content_type = format == "svg"   ? "image/svg+xml"
                         : format == "cli" ? "text/plain"
                                           : "application/octet-stream";
    }
  };
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
      layers();
      break;
    case JobKind::MaterialFit:
      out.flags.push_back("--json");
      out.output_name = "result.tsm";
      out.content_type = "application/octet-stream";
      break;
    case JobKind::MaterialSlice:
      if (options.value("colour", false) && options.value("format", "cli") != "png")
        throw InputError("options: colour: colours PNG masks; it needs \"format\": \"png\"");
      out.flags.push_back("--json");
      layers();
      break;
    case JobKind::MaterialIso:
      required("values", "the material values, one surface each, are required");
      out.flags.push_back("--json");
      out.output_name = "result.stl";
      out.content_type = "model/stl";
      break;
    case JobKind::Fill:
      break;
  }
  return out;
}

std::string command_output_name(const JobOptions& options) {
  const std::string& name = options.output_name;
  const std::string zip = ".zip";
  if (name.size() > zip.size() && name.compare(name.size() - zip.size(), zip.size(), zip) == 0)
    return name.substr(0, name.size() - zip.size());
  return name;
}

std::vector<std::string> job_command(JobKind kind, const JobOptions& options, const JobPaths& paths,
                                     std::uint64_t memory_budget) {
  // "material-fit" is `tpmsfill material fit`.
  const std::string name = job_kind_name(kind);
  const std::string material = "material-";
  std::vector<std::string> command = {name};
  if (name.rfind(material, 0) == 0) command = {"material", name.substr(material.size())};
  command.push_back(paths.input);
  if (!options.output_name.empty()) command.push_back(paths.output);
  command.insert(command.end(), options.flags.begin(), options.flags.end());
  if (!options.recipe.empty()) command.insert(command.end(), {"--recipe", paths.recipe});
  if (kind == JobKind::Fill || kind == JobKind::Slice) {
    command.insert(command.end(), {"--report", paths.report});
    command.insert(command.end(), {"--memory", std::to_string(memory_budget)});
  }
  return command;
}

}  // namespace tpmsfill::service
