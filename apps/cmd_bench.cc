// clothfit bench: the speed-accuracy sweep of every fitter
// (bench/bench.h).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "apps/commands.h"
#include "apps/progress.h"
#include "bench/bench.h"
#include "bench/stability.h"
#include "io/atomic_file.h"

namespace clothfit {

int RunBench(int argc, char** argv) {
  CommandArgs args(
      "bench",
      "clothfit bench [--quick] [--stability] [--repeats N] [--models LIST] "
      "--out DIR",
      "Sweeps the knobs that trade speed for accuracy (solver starts, "
      "iteration caps, lobes, lookup table,\ntolerance, threads, mip levels, "
      "linear solver) for each fitter on synthetic data with truth held out\n"
      "from the fit, beside SciPy least_squares peers of the same problems, "
      "and writes DIR/bench.csv (one row per\nconfiguration: median wall "
      "time with min/max, CPU time, peak memory, held-out error, parameter "
      "error),\nDIR/<model>_speed_accuracy.png (Pareto front, default "
      "ringed), DIR/<model>_size.png (lobes, tangent samples,\nmip levels: "
      "lafortune_mip_size.png) and DIR/summary.md. docs/bench.md explains "
      "the numbers.");
  args.Flag("quick", "small data and few knobs (seconds; the test suite's)");
  args.Flag("stability",
            "instead: success rate against noise, start distance, angular "
            "coverage and outliers (DIR/stability.*; --models: thread, "
            "cloth, slab, holes)");
  args.Option("repeats", "N", "timed runs per configuration", "3");
  args.Option("models", "LIST",
              "comma-separated: thread,cloth,lafortune,slab,holes", "all");
  args.Option("seed", "S", "random seed of the synthetic data", "1");
  args.Option("out", "DIR", "output folder (created if missing)");
  args.Flag("no-peer", "leave out the SciPy least_squares peers");
  args.Option("python", "PATH",
              "Python 3 with SciPy for the peer (python3-scipy)",
              "/usr/bin/python3 if present, else python3");
  args.Files({}, {});  // --out is a folder of new files
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string dir = args.Required("out");
  BenchOptions options;
  options.quick = args.Has("quick");
  const long repeats = args.GetInt("repeats");
  if (repeats < 1 || repeats > 100) {
    args.Fail("option '--repeats': must be in [1, 100]");
  }
  options.repeats = static_cast<int>(repeats);
  options.seed = static_cast<uint64_t>(args.GetInt("seed"));
  if (args.Has("models")) {
    for (const std::string& name : ListOption(args, "models")) {
      if (name != "thread" && name != "cloth" && name != "lafortune" &&
          name != "slab" && name != "holes") {
        args.Fail("option '--models': unknown model '" + name +
                  "' (thread, cloth, lafortune, slab, holes)");
      }
      options.models.push_back(name);
    }
  }
  ::mkdir(dir.c_str(), 0777);  // an existing folder is fine
  CheckWritable(dir + "/bench.csv");
  if (!args.Has("no-peer")) {
    options.peer_script = CLOTHFIT_PEER_SCRIPT;
    options.python = args.Has("python") ? args.Get("python")
                     : ::access("/usr/bin/python3", X_OK) == 0
                         ? "/usr/bin/python3"
                         : "python3";
    options.scratch_dir = dir;
  }
  // Each configuration on the progress line (a terminal only).
  auto task = std::make_shared<progress::Task>("bench", "");
  options.progress = [task](const std::string& what) { task->Say(what); };
  if (args.Has("stability")) {
    for (const std::string& file :
         WriteStabilityReport(RunStability(options), dir)) {
      std::printf("wrote %s\n", file.c_str());
    }
    return 0;
  }
  std::string peer_note;
  const std::vector<BenchRow> rows = clothfit::RunBench(options, &peer_note);
  if (!peer_note.empty())
    std::fprintf(stderr, "bench: %s\n", peer_note.c_str());
  WriteBenchCsv(rows, dir + "/bench.csv");
  std::printf("wrote %s/bench.csv\n", dir.c_str());
  for (const std::string& file :
       WriteBenchReport(rows, options, dir, peer_note)) {
    std::printf("wrote %s\n", file.c_str());
  }
  return 0;
}

}  // namespace clothfit
