#include "cli.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <new>

#include "rt/util/file_io.h"
#include "rt/util/isa.h"
#include "version.h"

namespace rtapp {

void setup_cli(CLI::App& app, const std::string& program, bool traces) {
    app.name(program);
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.set_help_flag("-h,--help", "this text");
    app.set_version_flag("--version", version_text(program, traces),
                         traces
                             ? "the version, the git commit it was built from, the ray kernels' ISA"
                             : "the version and the git commit it was built from");
    // Checked as it is parsed, before CLI11 reads it: CLI11 would wait on a FIFO forever and
    // read /dev/zero to the end.
    app.set_config("--config", "", "read options from a TOML or INI file (key = value)")
        ->type_name("FILE")
        ->check(CLI::Validator([](std::string& path) { return rt::regular_file_error(path); }, "",
                               "REGULAR_FILE"))
        ->trigger_on_parse();
    app.allow_config_extras(CLI::config_extras_mode::error);
}

int cli_exit(const CLI::App& app, const CLI::ParseError& e) {
    if (dynamic_cast<const CLI::CallForHelp*>(&e)) {
        std::printf("%s", app.help().c_str());
        return 0;
    }
    if (dynamic_cast<const CLI::CallForVersion*>(&e)) {
        std::printf("%s\n", e.what());
        return 0;
    }
    std::fprintf(stderr, "%s: %s (see %s --help)\n", app.get_name().c_str(), e.what(),
                 app.get_name().c_str());
    return 2;
}

bool isa_usable(const std::string& program) {
    if (rt::isa_error().empty()) return true;
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), rt::isa_error().c_str());
    return false;
}

std::string error_text(const std::exception& e, const std::string& doing) {
    if (dynamic_cast<const std::bad_alloc*>(&e)) return "out of memory while " + doing;
    return e.what();
}

}  // namespace rtapp
