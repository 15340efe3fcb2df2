// Usage errors: CLI11's exception texts ("At Most 1 required", "Could not convert: ...")
// mapped to one sentence each, naming the option and what it takes.
#include "cli/usage_errors.hpp"

#include <algorithm>
#include <vector>

namespace tpmsfill::cli {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The known name nearest `given`: the only one it abbreviates, else the closest within a
// third of its length (at least 2 edits); "" when none is near.
std::string nearest(const std::string& given, const std::vector<std::string>& known) {
  std::vector<std::string> extending;
  for (const std::string& k : known)
    if (k.size() > given.size() && k.compare(0, given.size(), given) == 0) extending.push_back(k);
  if (extending.size() == 1) return extending.front();
  if (given.size() <= 2) return "";  // "-q" is as near "-h" as to anything: no guess
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, given.size() / 3) + 1;
  for (const std::string& k : known)
    if (const std::size_t d = edit_distance(given, k); d < best_distance)
      best = k, best_distance = d;
  return best;
}

std::vector<std::string> option_names(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* o : command.get_options()) {
    for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
    for (const std::string& s : o->get_snames()) names.push_back("-" + s);
  }
  return names;
}

// The command named on the line, or null: the first argument naming one, then, while it has
// commands of its own ("field fit"), the next argument naming one of those.
const CLI::App* given_command(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* command = nullptr;
  const CLI::App* level = &app;
  for (int i = 1; i < argc && level; ++i) {
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : level->get_subcommands({}))
      if (sub->get_name() == argv[i]) next = sub;
    if (next) command = next, level = next;
  }
  return command;
}

// "fit" → "field fit": the command as typed after `tpmsfill`.
std::string full_name(const CLI::App& command) {
  std::string name = command.get_name();
  for (const CLI::App* p = command.get_parent(); p && p->get_parent(); p = p->get_parent())
    name = p->get_name() + " " + name;
  return name;
}

// The option of `command` whose name appears in CLI11's message (the longest such), or null.
const CLI::Option* option_in(const CLI::App* command, const std::string& message) {
  if (!command) return nullptr;
  const CLI::Option* found = nullptr;
  std::size_t length = 0;
  for (const CLI::Option* o : command->get_options()) {
    const std::string name = o->get_name();
    if (!name.empty() && name.size() > length && message.find(name) != std::string::npos)
      found = o, length = name.size();
  }
  return found;
}

std::string commands_list(const CLI::App& app) {
  std::string list;
  const auto subs = app.get_subcommands({});
  for (std::size_t i = 0; i < subs.size(); ++i)
    list += (i == 0 ? "" : i + 1 == subs.size() ? " or " : ", ") + subs[i]->get_name();
  return list;
}

std::string help_for(const CLI::App* command) {
  return command ? " (tpmsfill " + full_name(*command) + " --help)" : " (tpmsfill --help)";
}

// A command with commands of its own ("field") given none of them, or an unknown one.
std::string missing_command(const CLI::App& command, int argc, const char* const* argv) {
  std::vector<std::string> names;
  for (const CLI::App* sub : command.get_subcommands({})) names.push_back(sub->get_name());
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i] == command.get_name() && argv[i + 1][0] != '-') {
      const std::string near = nearest(argv[i + 1], names);
      return "unknown command '" + std::string(argv[i + 1]) + "' for " + full_name(command) +
             (near.empty() ? help_for(&command) : " (did you mean " + near + "?)");
    }
  return full_name(command) + " needs a command: " + commands_list(command) + help_for(&command);
}

std::string missing_arguments(const CLI::App& app, const CLI::App* command) {
  if (!command) return "a command is needed: " + commands_list(app) + help_for(nullptr);
  // A misspelt option is the likelier cause of a missing one (--hieght for --height).
  if (std::string extra = unplaced_arguments(*command); !extra.empty()) return extra;
  // What is required and was not given: positionals (IN, OUT) and required options (--height).
  std::vector<std::string> required;
  for (const CLI::Option* o : command->get_options())
    if (o->get_required() && o->count() == 0)
      required.push_back(o->get_positional() ? o->get_name(true) : o->get_name());
  std::string names;
  for (std::size_t i = 0; i < required.size(); ++i)
    names += (i == 0 ? "" : i + 1 == required.size() ? " and " : ", ") + required[i];
  return full_name(*command) + " needs " + names + help_for(command);
}

std::string count_mismatch(const CLI::Option* o, const CLI::App* command) {
  const int lo = o->get_expected_min(), hi = o->get_expected_max();
  const std::string name = o->get_name();
  if (hi == 0) return name + " takes no value";
  if (lo == hi)
    return name + (lo == 1 ? " needs a value" : " takes " + std::to_string(lo) + " values") +
           help_for(command);
  return name + " takes " + std::to_string(lo) + " to " + std::to_string(hi) + " values" +
         help_for(command);
}

// Whether `text` reads as a value of CLI11's type `type` ("INT", "UINT", "FLOAT", ...).
bool reads_as(const std::string& text, const std::string& type) {
  const bool whole = type.find("INT") != std::string::npos;
  std::size_t used = 0;
  try {
    if (whole)
      (void)std::stoll(text, &used);
    else
      (void)std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size() && !(whole && text[0] == '-' && type[0] == 'U');
}

std::string bad_value(const CLI::Option* o, const std::string& message) {
  const std::size_t eq = message.find(" = ");
  if (o->get_expected_max() == 0 || eq == std::string::npos)
    return o->get_name() + " takes no value";  // a switch given one ("--json=x")
  const std::string type = o->get_type_name();
  const bool whole = type.find("INT") != std::string::npos;
  const bool number = whole || type.find("FLOAT") != std::string::npos;
  // CLI11 joins all the values with ','; name the first that is wrong.
  std::string value = message.substr(eq + 3);
  if (number)
    for (std::size_t start = 0, end = 0; start <= value.size(); start = end + 1) {
      end = std::min(value.find(',', start), value.size());
      if (const std::string one = value.substr(start, end - start); !reads_as(one, type)) {
        value = one;
        break;
      }
    }
  return o->get_name() + ": '" + value + "' is not " +
         (whole    ? "a whole number"
          : number ? "a number"
                   : "a valid value");
}

}  // namespace

std::string usage_error(const CLI::App& app, const CLI::ParseError& error, int argc,
                        const char* const* argv) {
  const CLI::App* command = given_command(app, argc, argv);
  const std::string message = error.what();
  const CLI::Option* option = option_in(command, message);
  if (command && !command->get_subcommands({}).empty())
    return missing_command(*command, argc, argv);
  if (dynamic_cast<const CLI::RequiredError*>(&error)) return missing_arguments(app, command);
  if (option && dynamic_cast<const CLI::ArgumentMismatch*>(&error))
    return count_mismatch(option, command);
  if (option && dynamic_cast<const CLI::ConversionError*>(&error))
    return bad_value(option, message);
  if (option && dynamic_cast<const CLI::ValidationError*>(&error)) {
    // "NAME: MESSAGE" from our validators (validators.hpp).
    const std::string name = option->get_name(), said = message.substr(message.find(": ") + 2);
    return name + (said.rfind("must be", 0) == 0 ? " " : ": ") + said;
  }
  if (command) {
    if (std::string extra = unplaced_arguments(*command); !extra.empty()) return extra;
  }
  std::string text = message;
  if (!text.empty()) text[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
  return text + help_for(command);
}

std::string unplaced_arguments(const CLI::App& command) {
  const std::vector<std::string> left = command.remaining();
  if (left.empty()) return "";
  std::string given = left.front();
  if (given.size() > 1 && given[0] == '-') {
    given = given.substr(0, given.find('='));
    const std::string near = nearest(given, option_names(command));
    return "unknown option " + given + " for " + full_name(command) +
           (near.empty() ? help_for(&command) : " (did you mean " + near + "?)");
  }
  return "unexpected argument '" + given + "'" + help_for(&command);
}

std::string unknown_command(const CLI::App& app, int argc, const char* const* argv) {
  if (argc < 2 || std::string(argv[1]) == "--") return "";
  std::string given = argv[1];
  if (given.size() > 1 && given[0] == '-') {  // before the command: only --help or --version
    given = given.substr(0, given.find('='));
    const std::vector<std::string> known = option_names(app);
    if (std::find(known.begin(), known.end(), given) != known.end()) return "";
    const std::string near = nearest(given, known);
    return "unknown option " + given +
           (near.empty() ? help_for(nullptr) : " (did you mean " + near + "?)");
  }
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  if (std::find(names.begin(), names.end(), given) != names.end()) return "";
  const std::string near = nearest(given, names);
  return "unknown command '" + given + "'" +
         (near.empty() ? ": the commands are " + commands_list(app)
                       : " (did you mean " + near + "?)");
}

}  // namespace tpmsfill::cli
