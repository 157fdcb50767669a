// What every program's command line has in common (CLI11): -h,--help; --version; --config FILE
// (TOML or INI, keys the long option names, unknown keys an error); a repeated option takes its
// last value (scripts pass defaults first and forward the user's arguments after them); and the
// exit status of a usage error, 2.
#pragma once

#include <exception>
#include <string>

namespace CLI {
class App;
class ParseError;
}  // namespace CLI

namespace rtapp {

/// Sets up `app` for `program` as above. Call before adding the program's options. A program that
/// traces rays (`traces`) names its instruction set in --version.
void setup_cli(CLI::App& app, const std::string& program, bool traces = false);

/// After app.parse() threw: prints the help or version (stdout, exit 0) or the error and a hint
/// to --help (stderr, exit 2). Returns the exit status.
int cli_exit(const CLI::App& app, const CLI::ParseError& e);

/// False, after printing "PROGRAM: error: RAYTRACER_ISA=...: ..." to stderr, when the
/// environment asks for an instruction set that does not exist or that this CPU cannot run. The
/// programs that trace rays check it first and exit 2.
bool isa_usable(const std::string& program);

/// The message of an error that ends a program: e.what(), but for std::bad_alloc (whose what()
/// names only its type) "out of memory while <doing>".
std::string error_text(const std::exception& e, const std::string& doing);

}  // namespace rtapp
