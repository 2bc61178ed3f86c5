#include "hope/tools/cli.h"

#include <exception>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <boost/program_options.hpp>

namespace hope {
namespace tools {

int runTool(const char* tool, CommandLine (*command_line)(), int (*run)(const ParsedArgs&),
            int argc, char** argv) {
  try {
    const CommandLine table = command_line();
    const ParsedArgs args = table.parse(argc, argv);
    if (args.help) {
      std::cout << table.help();
      return 0;
    }
    return run(args);
  } catch (const std::invalid_argument& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
    return 1;
  }
}

namespace {

namespace po = boost::program_options;

// The help's layout, the same in every tool: lines of at most kWidth characters, explanations
// of options starting at kExplanationColumn.
constexpr std::size_t kWidth = 80;
constexpr std::size_t kExplanationColumn = 26;
constexpr std::size_t kOptionIndent = 2;

const char* const kHelpName = "--help";
const char* const kShortHelp = "-h";

std::invalid_argument argumentError(const std::string& message) {
  return std::invalid_argument(message + " (see --help)");
}

// How many columns `text` takes on a terminal: its UTF-8 characters ("§2.5", "2°").
std::size_t columns(const std::string& text) {
  std::size_t count = 0;
  for (const char c : text) count += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return count;
}

// `text` split into words at spaces, a double-quoted part ("0 0 0") kept in one word.
std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> result;
  std::string word;
  bool quoted = false;
  for (const char c : text) {
    if (c == ' ' && !quoted) {
      if (!word.empty()) result.push_back(word);
      word.clear();
      continue;
    }
    if (c == '"') quoted = !quoted;
    word += c;
  }
  if (!word.empty()) result.push_back(word);
  return result;
}

// Appends `text` to `out`, wrapped to kWidth: the first line continues at `column` (what the
// caller already wrote on it), the others start at `indent`. A '\n' in `text` starts a new
// line; a line of `text` that starts with a space is an example and is kept as it is.
void appendWrapped(std::string& out, const std::string& text, std::size_t column,
                   std::size_t indent) {
  std::istringstream lines(text);
  bool first_line = true;
  for (std::string line; std::getline(lines, line);) {
    if (!first_line) {
      out += "\n" + std::string(indent, ' ');
      column = indent;
    }
    first_line = false;
    if (!line.empty() && line[0] == ' ') {
      out += line;
      continue;
    }
    // Greedy filling, except that no line starts with an option ("--pose"): at the start of
    // a line of a section's note it would read as an option's entry. The words before it move
    // down with it.
    std::vector<std::vector<std::string>> rows(1);
    std::size_t row_column = column;
    for (const std::string& word : words(line)) {
      std::vector<std::string>& row = rows.back();
      if (!row.empty() && row_column + 1 + columns(word) > kWidth) {
        std::vector<std::string> carried{word};
        while (carried.front()[0] == '-' && row.size() > 1) {
          carried.insert(carried.begin(), row.back());
          row.pop_back();
        }
        row_column = indent + carried.size() - 1;
        for (const std::string& moved : carried) row_column += columns(moved);
        rows.push_back(std::move(carried));
        continue;
      }
      row_column += (row.empty() ? 0 : 1) + columns(word);
      row.push_back(word);
    }
    for (std::size_t r = 0; r < rows.size(); ++r) {
      if (r > 0) out += "\n" + std::string(indent, ' ');
      for (std::size_t w = 0; w < rows[r].size(); ++w) out += (w ? " " : "") + rows[r][w];
    }
  }
  out += "\n";
}

// One option's entry in the help: its name and placeholder, the explanation beside them (or
// below, when they reach into the explanations' column).
void appendOption(std::string& out, const std::string& synopsis, const std::string& explanation) {
  out += std::string(kOptionIndent, ' ') + synopsis;
  std::size_t column = kOptionIndent + columns(synopsis);
  if (column + 2 > kExplanationColumn) {
    out += "\n";
    column = 0;
  }
  out += std::string(kExplanationColumn - column, ' ');
  appendWrapped(out, explanation, kExplanationColumn, kExplanationColumn);
}

}  // namespace

CommandLine::CommandLine(std::string tool, std::vector<std::string> usage, std::string description)
    : tool_(std::move(tool)), usage_(std::move(usage)), description_(std::move(description)) {}

CommandLine& CommandLine::section(const std::string& title, const std::string& note) {
  sections_.push_back({title, note, {}});
  return *this;
}

CommandLine& CommandLine::value(const std::string& name, const std::string& placeholder,
                                const std::string& explanation) {
  add({name, placeholder, explanation, true});
  return *this;
}

CommandLine& CommandLine::flag(const std::string& name, const std::string& explanation) {
  add({name, "", explanation, false});
  return *this;
}

// A mistake in a tool's table is a bug of the tool, not of its user: std::logic_error (exit 1).
void CommandLine::add(Option option) {
  if (sections_.empty()) throw std::logic_error(tool_ + ": option table without a section");
  if (option.name.size() < 3 || option.name.compare(0, 2, "--") != 0 ||
      option.name.find_first_of("= ,", 2) != std::string::npos || option.name == kHelpName) {
    throw std::logic_error(tool_ + ": bad option name '" + option.name + "'");
  }
  for (const Section& section : sections_) {
    for (const Option& known : section.options) {
      if (known.name == option.name) {
        throw std::logic_error(tool_ + ": option '" + option.name + "' listed twice");
      }
    }
  }
  sections_.back().options.push_back(std::move(option));
}

std::string CommandLine::help() const {
  std::string out;
  for (std::size_t i = 0; i < usage_.size(); ++i) {
    const std::string start = (i == 0 ? "usage: " : "       ") + tool_ + " ";
    out += start;
    appendWrapped(out, usage_[i], columns(start), columns(start));
  }
  out += "\n";
  appendWrapped(out, description_, 0, 0);
  for (const Section& section : sections_) {
    out += "\n";
    appendWrapped(out, section.title + ":", 0, 0);
    if (!section.note.empty()) {
      out += std::string(kOptionIndent, ' ');
      appendWrapped(out, section.note, kOptionIndent, kOptionIndent);
    }
    for (const Option& option : section.options) {
      appendOption(out, option.takes_value ? option.name + " " + option.placeholder : option.name,
                   option.explanation);
    }
  }
  out += "\ngeneral:\n";
  appendOption(out, std::string(kShortHelp) + ", " + kHelpName, "print this help and exit");
  return out;
}

ParsedArgs CommandLine::parse(int argc, const char* const* argv) const {
  // The table as program_options sees it: names without the leading "--".
  po::options_description described;
  std::map<std::string, const Option*> by_key;
  for (const Section& section : sections_) {
    for (const Option& option : section.options) {
      const std::string key = option.name.substr(2);
      by_key[key] = &option;
      if (option.takes_value) {
        described.add_options()(key.c_str(), po::value<std::string>(), "");
      } else {
        described.add_options()(key.c_str(), "");
      }
    }
  }
  const std::string help_key = std::string(kHelpName).substr(2);
  described.add_options()(help_key.c_str(), "");

  auto asksForHelp = [&] {
    for (int i = 1; i < argc; ++i) {
      if (argv[i] == std::string(kHelpName) || argv[i] == std::string(kShortHelp)) return true;
    }
    return false;
  };

  // Long options only: with short options (or guessing) on, program_options would read a
  // value such as "-1" or "-0.1 0 0" as options of their own. Unknown options and stray
  // arguments are let through (allow_unregistered) to be reported here in one style.
  namespace style = po::command_line_style;
  po::parsed_options parsed(&described);
  try {
    parsed = po::command_line_parser(argc, argv)
                 .options(described)
                 .style(style::allow_long | style::long_allow_adjacent | style::long_allow_next)
                 .allow_unregistered()
                 .run();
  } catch (const po::error& e) {
    // A broken command line that asks for help gets the help (here any "-h" asks: the
    // parse that would tell an option's value from an option failed).
    if (asksForHelp()) {
      ParsedArgs help;
      help.help = true;
      return help;
    }
    const auto* syntax = dynamic_cast<const po::invalid_command_line_syntax*>(&e);
    if (syntax) {
      const std::string name = syntax->get_option_name();
      switch (syntax->kind()) {
        case po::invalid_command_line_syntax::missing_parameter:
        case po::invalid_command_line_syntax::empty_adjacent_parameter:
          throw argumentError(name + " needs a value");
        case po::invalid_command_line_syntax::extra_parameter:
          throw argumentError(name + " takes no value");
        default:
          break;
      }
    }
    throw argumentError(e.what());
  }

  ParsedArgs args;
  // Help wins over any other problem of the command line, even when "--help" was taken as
  // an option's value ("--json --help"); "-h" as an option's value ("--out -h") is a value.
  for (const po::option& given : parsed.options) {
    const bool positional = given.position_key >= 0 || given.string_key.empty();
    for (const std::string& token : given.original_tokens) {
      if (token == kHelpName || (positional && token == kShortHelp)) {
        args.help = true;
        return args;
      }
    }
  }
  for (const po::option& given : parsed.options) {
    if (given.position_key >= 0 || given.string_key.empty()) {
      // Not an option: with short options off, "-x" lands here too.
      const std::string& text =
          given.original_tokens.empty() ? given.value.front() : given.original_tokens.front();
      if (text.size() > 1 && text[0] == '-') throw argumentError("unknown option '" + text + "'");
      throw argumentError("unexpected argument '" + text + "': options start with --");
    }
    const std::string name = "--" + given.string_key;
    if (given.unregistered) throw argumentError("unknown option '" + name + "'");
    const Option& option = *by_key.at(given.string_key);
    if (args.values.count(name) || args.flags.count(name)) {
      throw argumentError(name + " given more than once");
    }
    if (!option.takes_value) {
      args.flags.insert(name);
      continue;
    }
    const std::string& value = given.value.front();
    // program_options takes whatever follows as the value, even "--quiet" in
    // "--json --quiet": a value starting with "--" is taken only after '='.
    const bool separate = given.original_tokens.size() > 1;
    if (separate && value.compare(0, 2, "--") == 0) {
      throw argumentError(name + " needs a value, not '" + value + "'; write " + name + "=" +
                          value + " if that is the value");
    }
    args.values[name] = value;
  }
  return args;
}

int leadingInt(const std::string& option, const std::string& text) {
  try {
    return std::stoi(text);
  } catch (const std::logic_error&) {  // std::invalid_argument or std::out_of_range
    throw std::invalid_argument(option + " needs a whole number, not '" + text + "'");
  }
}

double leadingDouble(const std::string& option, const std::string& text) {
  try {
    return std::stod(text);
  } catch (const std::logic_error&) {
    throw std::invalid_argument(option + " needs a number, not '" + text + "'");
  }
}

}  // namespace tools
}  // namespace hope
