// The command-line tools' shared front end: one way to read arguments, one shape of help and
// one error convention for all of them.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace hope {
namespace tools {

// What a command line asked for, keyed by the option names of the tool's table ("--r-xy").
struct ParsedArgs {
  // --help or -h was given: the tool prints CommandLine::help() and does nothing else.
  bool help = false;
  // The value of each valued option given ("--r-xy 0.3" and "--r-xy=0.3" alike).
  std::map<std::string, std::string> values;
  // The flags given.
  std::set<std::string> flags;

  bool flag(const std::string& name) const { return flags.count(name) > 0; }
};

// A tool's options as one table, from which both the parser (boost::program_options) and the
// help are made, so that every tool reads its arguments and explains them the same way:
//
//   CommandLine cl("hope_extract", {"--input FILE [options]"}, "Finds the horizontal planes …");
//   cl.section("input").value("--input", "FILE", "point cloud, .pcd or .ply …");
//   cl.section("output").value("--json", "FILE", "every plane field as JSON")
//       .flag("--quiet", "no table on stdout");
//   const ParsedArgs args = cl.parse(argc, argv);
//   if (args.help) { std::cout << cl.help(); return 0; }
//
// Rules of the command line: only long options; a value follows its option as the next
// argument or after '=' ("--r-xy 0.3", "--r-xy=0.3"), and may start with a single '-'
// ("--min-height -1", "--rpy \"-0.1 0 0\""); a flag takes no value; each option at most once;
// no other arguments. --help and -h are always there.
class CommandLine {
 public:
  // `usage`: the ways to call the tool, each without the tool's name ("--out DIR [options]");
  // `description`: one paragraph on what the tool does.
  CommandLine(std::string tool, std::vector<std::string> usage, std::string description);

  // Starts a group of options in the help, under `title`; `note`, when given, is a paragraph
  // printed below the title (a line starting with spaces is kept as it is: an example).
  CommandLine& section(const std::string& title, const std::string& note = "");
  // An option with a value; `placeholder` names the value in the help ("FILE").
  CommandLine& value(const std::string& name, const std::string& placeholder,
                     const std::string& explanation);
  // An option without a value.
  CommandLine& flag(const std::string& name, const std::string& explanation);

  // The help text: the usage lines, the description, then every section with its options.
  std::string help() const;

  // Reads the arguments. Throws std::invalid_argument, its message naming the argument and
  // ending in "(see --help)", for an unknown option, a missing value, a value given to a
  // flag, an option given twice, or an argument that is not an option.
  ParsedArgs parse(int argc, const char* const* argv) const;

 private:
  struct Option {
    std::string name, placeholder, explanation;
    bool takes_value;
  };
  struct Section {
    std::string title, note;
    std::vector<Option> options;
  };
  void add(Option option);

  std::string tool_;
  std::vector<std::string> usage_;
  std::string description_;
  std::vector<Section> sections_;
};

// The leading whole number or number of an option's value, as std::stoi / std::stod read it
// (the rest of the text is ignored), but an error naming the option (std::invalid_argument)
// when the value does not start with one or is out of range.
int leadingInt(const std::string& option, const std::string& text);
double leadingDouble(const std::string& option, const std::string& text);

// A tool's main: reads the arguments by the tool's table (`command_line()`), prints the help
// for --help or -h, otherwise returns `run(args)`. An exception ends the tool with
// "<tool>: error: <what>" on stderr and exit code 2 for std::invalid_argument (bad arguments
// or values) or 1 for anything else (unreadable or unwritable files, …).
int runTool(const char* tool, CommandLine (*command_line)(), int (*run)(const ParsedArgs&),
            int argc, char** argv);

}  // namespace tools
}  // namespace hope
