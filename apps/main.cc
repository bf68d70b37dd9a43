// clothfit: fits cloth appearance models to measurement tables (docs/cli.md).
#include <glog/logging.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/full_binary.h"
#include "apps/progress.h"
#include "io/input_error.h"
#include "io/text_util.h"

// The project version, from CMake's project(VERSION ...) (apps/CMakeLists.txt).
#ifndef CLOTHFIT_VERSION
#error "CLOTHFIT_VERSION must be defined by the build"
#endif

namespace {

// clothfit version (and clothfit --version): "clothfit X.Y.Z".
int RunVersion(int argc, char** argv) {
  clothfit::CommandArgs args("version", "clothfit version | clothfit --version",
                             "Prints the version of clothfit.");
  if (!args.Parse(argc, argv, 2)) return 0;
  std::cout << "clothfit " << CLOTHFIT_VERSION << "\n";
  return 0;
}

struct Command {
  const char* name;
  int (*run)(int, char**);
  const char* summary;
};

#ifdef CLOTHFIT_LIGHT
// The commands that read or write images run in clothfit-full
// (apps/full_binary.h).
int RunFull(int, char**) { clothfit::RunInFullBinary(); }
#define CLOTHFIT_IMAGES(run) RunFull
#else
#define CLOTHFIT_IMAGES(run) run
#endif

const Command kCommands[] = {
    {"bench", CLOTHFIT_IMAGES(clothfit::RunBench),
     "speed against accuracy of every fitter"},
    {"blocks", CLOTHFIT_IMAGES(clothfit::RunBlocks),
     "the blocks of an image stack's texture (fit --region, docs/scale.md)"},
    {"eval", clothfit::RunEval, "evaluate a parameter file at directions"},
    {"export", clothfit::RunExport,
     "a fitted model as a glTF 2.0 cloth (KHR_materials_sheen)"},
    {"fit", clothfit::RunFit, "fit a model to a measurement table"},
    {"holes", CLOTHFIT_IMAGES(clothfit::RunHoles),
     "semi-transparent textures with thickness (analyze|eval|truth)"},
    {"merge", CLOTHFIT_IMAGES(clothfit::RunMerge),
     "merge the parts of a texel map fitted in blocks (fit --region)"},
    {"plot", CLOTHFIT_IMAGES(clothfit::RunPlot),
     "figures of a model against a table (scatter, residuals, polar, ...)"},
    {"preset", clothfit::RunPreset, "print a preset fabric's parameter file"},
    {"presets", clothfit::RunPresets, "list the preset fabrics"},
    {"render", CLOTHFIT_IMAGES(clothfit::RunRender),
     "preview renders of parameter files"},
    {"report", CLOTHFIT_IMAGES(clothfit::RunReport),
     "one HTML page of a fit: figures, parameters, an interactive sphere"},
    {"synth", clothfit::RunSynth, "write a synthetic measurement table"},
    {"version", RunVersion, "print the version (also --version)"},
};

void PrintUsage(std::ostream& out) {
  out << "usage: clothfit <command> [options]\n"
         "       clothfit <command> --help   (or clothfit help <command>)\n"
         "       clothfit --version\n"
         "\ncommands:\n";
  for (const Command& c : kCommands) {
    out << "  " << c.name << std::string(10 - std::strlen(c.name), ' ')
        << c.summary << "\n";
  }
  out << "\nexit status: 0 success, 1 a fit without a usable solution, "
         "2 bad input or usage\n";
}

const Command* FindCommand(const std::string& name) {
  for (const Command& c : kCommands) {
    if (name == c.name) return &c;
  }
  return nullptr;
}

// One line, like every bad input: the unknown name, the commands, and where
// the usage is. `context` is "" or e.g. "clothfit help: ".
int UnknownCommand(const std::string& context, const std::string& name) {
  std::string names;
  std::vector<std::string> candidates;
  for (const Command& c : kCommands) {
    names += (names.empty() ? "" : ", ") + std::string(c.name);
    candidates.push_back(c.name);
  }
  std::cerr << "error: " << context << "unknown command '"
            << clothfit::text_util::EscapeControl(name) << "'"
            << clothfit::text_util::DidYouMean(name, candidates)
            << " (commands: " << names << "; see 'clothfit --help')\n";
  return 2;
}

// What a command printed (a parameter file, a summary, its help) is its
// output: a failed write of standard output (a full disk) is an error,
// never exit 0. Both streams: the summaries use std::cout and printf.
int Finish(int status) {
  clothfit::progress::FlushWarnings();
  clothfit::progress::Clear();
  std::cout.flush();
  const bool failed =
      !std::cout || std::fflush(stdout) != 0 || std::ferror(stdout) != 0;
  if (!failed) return status;
  std::cerr << "error: standard output: cannot write"
            << (errno != 0 ? std::string(": ") + std::strerror(errno)
                           : std::string())
            << "\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  // Ceres logs a failed solve through glog, to stderr (logging is not
  // initialised); the fit reports every such failure in its own message,
  // so that bad input gets one clear message.
  FLAGS_minloglevel = google::GLOG_FATAL;
  if (argc < 2) {
    std::cerr << "error: no command given (see 'clothfit --help')\n";
    return 2;
  }
  std::string name = argv[1];
  if (name == "--help" || name == "-h" || (name == "help" && argc == 2)) {
    PrintUsage(std::cout);
    return Finish(0);
  }
  if (name == "--version") name = "version";
  // clothfit help CMD [ARGS...] runs clothfit CMD [ARGS...] --help, so that
  // it prints exactly that help (e.g. clothfit help synth --model slab).
  std::vector<char*> help_argv;
  static char help_flag[] = "--help";
  if (name == "help") {
    name = argv[2];
    if (FindCommand(name) == nullptr) {
      return UnknownCommand("clothfit help: ", name);
    }
    help_argv.push_back(argv[0]);
    for (int i = 2; i < argc; ++i) help_argv.push_back(argv[i]);
    help_argv.push_back(help_flag);
    argc = static_cast<int>(help_argv.size());
    help_argv.push_back(nullptr);  // argv[argc] is null, as for main
    argv = help_argv.data();
  }
  const Command* c = FindCommand(name);
  if (c == nullptr) return UnknownCommand("", name);
  clothfit::SetProgramArguments(argc, argv);
  try {
    return Finish(c->run(argc, argv));
  } catch (const clothfit::InputError& e) {
    clothfit::progress::Clear();
    std::cerr << "error: " << clothfit::text_util::EscapeControl(e.what())
              << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "internal error: "
              << clothfit::text_util::EscapeControl(e.what()) << "\n";
    return 3;
  }
}
