// Command-line handling shared by the benchmark binaries: our own --quick flag is taken out before Google
// Benchmark sees the rest, and --benchmark_format is limited to what the summary reporters support.
//
//   BenchArguments arguments = parseBenchArguments(argc, argv, "features_bench");
//   if (!arguments.ok) return 1;
//
// Thread contract: call once from main().
#pragma once

#include <benchmark/benchmark.h>

#include <cstring>
#include <iostream>
#include <string>
#include <vector>

struct BenchArguments {
  bool ok = false;
  bool quick = false;              // one short pass, a smoke check
  std::string format = "console";  // console or json
};

inline BenchArguments parseBenchArguments(int argc, char** argv, const char* program) {
  BenchArguments result;
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick") {
      result.quick = true;
      continue;
    }
    if (arg.rfind("--benchmark_format=", 0) == 0) result.format = arg.substr(std::strlen("--benchmark_format="));
    args.push_back(argv[i]);
  }
  if (result.format != "console" && result.format != "json") {
    std::cerr << program << ": --benchmark_format must be console or json\n";
    return result;
  }
  int benchArgc = static_cast<int>(args.size());
  benchmark::Initialize(&benchArgc, args.data());
  result.ok = !benchmark::ReportUnrecognizedArguments(benchArgc, args.data());
  return result;
}
