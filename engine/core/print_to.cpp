#include "core/print_to.h"

#include <cstdarg>
#include <cstdio>
#include <vector>

namespace th {

void printTo(std::ostream& out, const char* format, ...) {
  std::va_list arguments;
  va_start(arguments, format);
  std::va_list again;
  va_copy(again, arguments);
  const int length = std::vsnprintf(nullptr, 0, format, arguments);
  va_end(arguments);
  if (length > 0) {
    std::vector<char> text(static_cast<std::size_t>(length) + 1);
    std::vsnprintf(text.data(), text.size(), format, again);
    out.write(text.data(), length);
  }
  va_end(again);
}

}  // namespace th
