// printf's formats onto a std::ostream: what a report writes, into a stream a test can read as well as stdout.
//
//   th::printTo(out, "  %-16s %6.2f\n", name.c_str(), score);
//
// The text is exactly what std::printf would print with the same format and values. Thread contract: as the
// stream's own.
#pragma once

#include <ostream>

namespace th {

void printTo(std::ostream& out, const char* format, ...) __attribute__((format(printf, 2, 3)));

}  // namespace th
