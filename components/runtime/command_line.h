#pragma once
// The command line of every dmpl executable, parsed by CLI11 the same way: --help lists every
// flag and exits 0; a bad value, a missing one or an unknown flag is one line on stderr and exit
// 2 (README, "Exit codes"); `--key value` and `--key=value` both work.
#include <charconv>
#include <iostream>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace dmpl {

// Parses argv into `app`. Returns the exit code when the process is to exit now: 0 after --help
// (printed on stdout), 2 after a command-line error; nothing when it is to go on.
inline std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help (CLI11 signals it by an exception too)
      std::cout << app.help();
      return 0;
    }
    // One line, where CLI11's own handler adds a second.
    std::cerr << app.get_name() << ": " << e.what() << " (try --help)\n";
    return 2;
  }
  return std::nullopt;
}

// Integers from `min` up, refused with what was given: "--steps: expected an integer >= 1, got
// 'x'" (CLI11's own range check prints the type's whole range). The bound is for the flag's
// description to say: the help shows the type alone.
inline CLI::Validator IntegerAtLeast(int min) {
  return CLI::Validator(
      [min](std::string& text) {
        int value = 0;
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (error == std::errc() && stop == end && value >= min) return std::string();
        return "expected an integer >= " + std::to_string(min) + ", got '" + text + "'";
      },
      "");
}

}  // namespace dmpl
