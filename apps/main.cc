// clothfit: fits cloth appearance models to measurement tables (SPEC §5).
#include <glog/logging.h>

#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "apps/commands.h"
#include "io/input_error.h"

namespace {

struct Command {
  const char* name;
  int (*run)(int, char**);
  const char* summary;
};

const Command kCommands[] = {
    {"bench", clothfit::RunBench, "speed against accuracy of every fitter"},
    {"eval", clothfit::RunEval, "evaluate a parameter file at directions"},
    {"fit", clothfit::RunFit, "fit a model to a measurement table"},
    {"holes", clothfit::RunHoles,
     "semi-transparent textures with thickness (analyze|eval|truth)"},
    {"plot", clothfit::RunPlot, "polar plots: measured values against a model"},
    {"preset", clothfit::RunPreset, "print a preset fabric's parameter file"},
    {"presets", clothfit::RunPresets, "list the preset fabrics"},
    {"render", clothfit::RunRender, "preview renders of parameter files"},
    {"synth", clothfit::RunSynth, "write a synthetic measurement table"},
};

void PrintUsage(std::ostream& out) {
  out << "usage: clothfit <command> [options]   (clothfit <command> --help)\n"
         "\ncommands:\n";
  for (const Command& c : kCommands) {
    out << "  " << c.name << std::string(10 - std::strlen(c.name), ' ')
        << c.summary << "\n";
  }
  out << "\nexit status: 0 success, 1 a fit without a usable solution, "
         "2 bad input or usage\n";
}

}  // namespace

int main(int argc, char** argv) {
  // Ceres logs a failed solve through glog, to stderr (logging is not
  // initialised); the fit reports every such failure in its own message,
  // so that bad input gets one clear message (issue 8).
  FLAGS_minloglevel = google::GLOG_FATAL;
  if (argc < 2) {
    PrintUsage(std::cerr);
    return 2;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    PrintUsage(std::cout);
    return 0;
  }
  for (const Command& c : kCommands) {
    if (name != c.name) continue;
    try {
      return c.run(argc, argv);
    } catch (const clothfit::InputError& e) {
      std::cerr << "error: " << e.what() << "\n";
      return 2;
    } catch (const std::bad_alloc&) {
      std::cerr << "error: out of memory\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "internal error: " << e.what() << "\n";
      return 3;
    }
  }
  // One line, like every bad input: the commands, and where the usage is.
  std::string names;
  for (const Command& c : kCommands)
    names += (names.empty() ? "" : ", ") + std::string(c.name);
  std::cerr << "error: unknown command '" << name << "' (commands: " << names
            << "; see 'clothfit --help')\n";
  return 2;
}
