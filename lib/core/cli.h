// CLI11 helpers shared by the tools, so that an option means and reads the same in each:
// enum options named by their EnumNames table, options whose text a parsing function reads
// (its sss::Error becomes CLI11's error, after the option's name), number triples, and the
// --threads and --quiet options. Header-only and included by tools/ only: the libraries do not
// depend on CLI11. Errors found here are usage errors (exit 2, see core/tool.h).
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/format.h"

namespace sss::cli {

// "" when `f()` returns, else the message of the sss::Error it throws: what a CLI11 validator
// returns.
template <typename F>
std::string errorMessageOf(F f) {
  try {
    f();
    return {};
  } catch (const Error& e) {
    return e.what();
  }
}

// A check that `parse(text)` (a function that throws sss::Error on bad text) accepts the
// option's text; the Error's message is CLI11's: "--sky: elevation must be in [0, 90] degrees".
template <typename Parse>
CLI::Validator parsedBy(Parse parse) {
  return CLI::Validator([parse](std::string& text) { return errorMessageOf([&] { parse(text); }); },
                        "");
}

// A check that converts the option's text as CLI11 will (to T) and passes the value to `check`,
// a library function that throws sss::Error on a value outside its model: the library owns the
// range, CLI11 adds the flag ("--eta: eta must be a positive number"). Text that does not
// convert is left to CLI11's conversion error.
template <typename T, typename Check>
CLI::Validator checkedBy(Check check) {
  return CLI::Validator(
      [check](std::string& text) -> std::string {
        T value{};
        if (!CLI::detail::lexical_cast(text, value)) return {};
        return errorMessageOf([&] { check(value); });
      },
      "");
}

// A check that the option's number is finite and at least `min` ("--tolerance: must be a finite
// number >= 0, got '-1'"); CLI::Range lets NaN through and prints its double bounds in full.
inline CLI::Validator finiteAtLeast(double min) {
  return CLI::Validator(
      [min](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return {};  // CLI11's conversion error
        if (std::isfinite(value) && value >= min) return {};
        return "must be a finite number >= " + format("%g", min) + ", got '" + text + "'";
      },
      "");
}

// A check that the option's number is finite and within [min, max] (defaults: any finite
// number): "--fov: must be a finite number in [1, 170], got 'nan'".
inline CLI::Validator finiteIn(double min = -HUGE_VAL, double max = HUGE_VAL) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return {};  // CLI11's conversion error
        if (std::isfinite(value) && value >= min && value <= max) return {};
        const bool any = std::isinf(min) && std::isinf(max);
        return "must be a finite number" +
               (any ? std::string()
                    : " in [" + format("%g", min) + ", " + format("%g", max) + "]") +
               ", got '" + text + "'";
      },
      "");
}

// An option whose text `parse` turns into `value` (checked by parsedBy first, so the assignment
// after parsing cannot fail).
template <typename T, typename Parse>
CLI::Option* addParsedOption(CLI::App& app, const std::string& name, T& value, Parse parse,
                             const std::string& description) {
  return app
      .add_option_function<std::string>(
          name, [&value, parse](const std::string& text) { value = parse(text); }, description)
      ->check(parsedBy(parse));
}

// An option that takes the names of `names` and sets `value`; --help shows "a|b|c" and the
// default by name. An unknown name fails with the table's message: "--method: unknown irradiance
// method 'fast' (use auto, brute or sh)". (CLI::CheckedTransformer(names.map()) would also take
// the enum's numbers, "--method 2", and name the choices as "{auto->0,brute->1,sh->2}".)
template <typename E, std::size_t N>
CLI::Option* addEnumOption(CLI::App& app, const std::string& name, E& value,
                           const EnumNames<E, N>& names, const std::string& description) {
  CLI::Validator toNumber(
      [names](std::string& text) {
        // CLI11 then converts the enum from its number.
        return errorMessageOf([&] {
          text = std::to_string(static_cast<std::underlying_type_t<E>>(names.parse(text)));
        });
      },
      "");
  return app.add_option(name, value, description)
      ->transform(toNumber)
      ->type_name(names.choices("|"))
      ->default_str(names.name(value));
}

// "a,b,c": three finite numbers in T's precision, each converted as CLI11 converts an option's
// number; with `allowOne`, one number stands for all three ("0.5": grey). Throws Error.
template <typename T>
glm::vec<3, T> parseTriple(const std::string& text, bool allowOne = false) {
  std::vector<T> values;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t comma = text.find(',', begin);
    T v{};
    if (!CLI::detail::lexical_cast(text.substr(begin, comma - begin), v) || !std::isfinite(v)) {
      values.clear();
      break;
    }
    values.push_back(v);
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  if (values.size() == 3) return {values[0], values[1], values[2]};
  if (allowOne && values.size() == 1) return glm::vec<3, T>(values[0]);
  throw Error(std::string(allowOne ? "expected one number or three" : "expected three") +
              " comma-separated finite numbers, got '" + text + "'");
}

// --threads N: worker threads, <= 0 for all cores (the outputs do not depend on it).
inline CLI::Option* addThreadsOption(CLI::App& app, int& threads) {
  return app.add_option("--threads", threads, "Worker threads (0: all cores)")
      ->capture_default_str();
}

// -q,--quiet: no progress or informational messages on stderr (warnings and errors remain).
inline CLI::Option* addQuietFlag(CLI::App& app, bool& quiet) {
  return app.add_flag("-q,--quiet", quiet, "No progress or informational messages");
}

}  // namespace sss::cli
