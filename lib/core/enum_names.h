// One name table per enum, used for parsing, printing and --help (and CLI11's transformers):
//
//   inline constexpr EnumNames<Color, 2> kColorNames{"colour", {{{Color::Red, "red"},
//                                                                {Color::Blue, "blue"}}}};
//   kColorNames.parse("red");   // Color::Red; an unknown name throws Error naming the choices
//   kColorNames.name(Color::Blue);   // "blue"
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace sss {

template <typename E>
struct EnumName {
  E value;
  const char* name;
};

template <typename E, std::size_t N>
struct EnumNames {
  const char* what;  // the kind of thing named, for errors: "diffusion method"
  std::array<EnumName<E>, N> entries;

  const char* name(E value) const {
    for (const EnumName<E>& e : entries)
      if (e.value == value) return e.name;
    return "?";
  }
  // The value named `text`, or nothing.
  std::optional<E> find(std::string_view text) const {
    for (const EnumName<E>& e : entries)
      if (text == e.name) return e.value;
    return std::nullopt;
  }
  // Throws Error("unknown <what> '<text>' (use a, b or c)"), control characters escaped: the text
  // may come from a file.
  E parse(std::string_view text) const {
    if (const std::optional<E> value = find(text)) return *value;
    fail("", "unknown " + std::string(what) + " '" + std::string(text) + "' (use " +
                 choices(", ", " or ") + ")");
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const EnumName<E>& e : entries) out.emplace_back(e.name);
    return out;
  }
  // "a|b|c" for --help, or "a, b or c" for messages.
  std::string choices(const char* separator = "|", const char* last = nullptr) const {
    std::string out;
    for (std::size_t i = 0; i < N; ++i) {
      if (i > 0) out += (last && i + 1 == N) ? last : separator;
      out += entries[i].name;
    }
    return out;
  }
  // Name -> value, for CLI::CheckedTransformer.
  std::map<std::string, E> map() const {
    std::map<std::string, E> out;
    for (const EnumName<E>& e : entries) out.emplace(e.name, e.value);
    return out;
  }
};

}  // namespace sss
