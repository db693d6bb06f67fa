#pragma once
// An option table: each command-line option written once, as a row that
// binds it to a field of an options struct S. From the rows come the CLI11
// registration, the default shown by --help (read from a struct, never
// written again), the unit, the group, the copy of the options the user gave
// onto a preset (an option not given never overrides the preset) and the
// Markdown reference (docs/walk-options.md).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hw::app {

template <class S>
struct OptionRow {
  std::string name;      // long name, e.g. "--near"
  std::string negation;  // a flag pair's other name ("--no-merge-strips"); empty otherwise
  std::string group;     // --help group: Essentials, Level of detail, Composition, ...
  std::string unit;      // e.g. "ms", "scene units"; empty: none (a name, a count)
  std::string help;
  bool flag = false;     // takes no value
  // Registers the option(s) on `c`, writing what the user gives into *parsed.
  std::function<CLI::Option*(CLI::App* c, S* parsed, const std::string& description)> bind;
  // The value as a user writes it ("auto", "0.125", "on").
  std::function<std::string(const S&)> show;
  // Sets the fields this option sets, from `parsed` into `out`.
  std::function<void(const S& parsed, S* out)> copy;
};

template <class S>
using OptionRows = std::vector<OptionRow<S>>;

// "%g" of a double; whole numbers as integers.
inline std::string formatOptionNumber(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

namespace options_detail {
template <class T>
std::string showValue(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "on" : "off";
  else if constexpr (std::is_floating_point_v<T>) return formatOptionNumber(static_cast<double>(v));
  else if constexpr (std::is_integral_v<T>) return std::to_string(v);
  else return v;
}
}  // namespace options_detail

// A field reached from the struct: `[](S& s) -> T& { return s.lod.tau; }`.
template <class S, class T>
using FieldOf = T& (*)(S&);

// A value option bound straight to a field (numbers, strings).
template <class S, class T>
OptionRow<S> valueRow(std::string name, FieldOf<S, T> field, std::string group, std::string unit,
                      std::string help, std::optional<CLI::Validator> check = std::nullopt) {
  OptionRow<S> r;
  r.name = std::move(name);
  r.group = std::move(group);
  r.unit = std::move(unit);
  r.help = std::move(help);
  r.bind = [field, check, optName = r.name](CLI::App* c, S* s, const std::string& d) {
    CLI::Option* o = c->add_option(optName, field(*s), d);
    if (check) o->check(*check);
    return o;
  };
  r.show = [field](const S& s) { return options_detail::showValue(field(const_cast<S&>(s))); };
  r.copy = [field](const S& from, S* to) { field(*to) = field(const_cast<S&>(from)); };
  return r;
}

// A flag pair "--x,!--no-x" bound to a bool field.
template <class S>
OptionRow<S> togglePair(std::string name, std::string negation, FieldOf<S, bool> field,
                        std::string group, std::string help) {
  OptionRow<S> r;
  r.name = std::move(name);
  r.negation = std::move(negation);
  r.group = std::move(group);
  r.help = std::move(help);
  r.flag = true;
  r.bind = [field, names = r.name + ",!" + r.negation](CLI::App* c, S* s, const std::string& d) {
    return c->add_flag(names, field(*s), d);
  };
  r.show = [field](const S& s) { return field(const_cast<S&>(s)) ? std::string("on") : "off"; };
  r.copy = [field](const S& from, S* to) { field(*to) = field(const_cast<S&>(from)); };
  return r;
}

// A lone flag that sets a bool field to `whenGiven` ("--no-sky-backdrop" sets
// skyBackdrop = false). Shown as on when the field's default is `whenGiven`.
template <class S>
OptionRow<S> flagRow(std::string name, FieldOf<S, bool> field, bool whenGiven, std::string group,
                     std::string help) {
  OptionRow<S> r;
  r.name = std::move(name);
  r.group = std::move(group);
  r.help = std::move(help);
  r.flag = true;
  r.bind = [field, whenGiven, optName = r.name](CLI::App* c, S* s, const std::string& d) {
    return c->add_flag_callback(optName, [field, whenGiven, s] { field(*s) = whenGiven; }, d);
  };
  r.show = [field, whenGiven](const S& s) {
    return field(const_cast<S&>(s)) == whenGiven ? std::string("on") : "off";
  };
  r.copy = [field](const S& from, S* to) { field(*to) = field(const_cast<S&>(from)); };
  return r;
}

// Names of an enum's values, from the module that owns them: the one place
// the names are written. `values` lists every value.
template <class E>
std::vector<std::pair<std::string, E>> enumNames(const std::vector<E>& values,
                                                 const char* (*nameOf)(E)) {
  std::vector<std::pair<std::string, E>> out;
  for (E v : values) out.emplace_back(nameOf(v), v);
  return out;
}

// An option whose value is one name of `names`, bound to a field of type E.
template <class S, class E>
OptionRow<S> choiceRow(std::string name, FieldOf<S, E> field,
                       std::vector<std::pair<std::string, E>> names, std::string group,
                       std::string help) {
  OptionRow<S> r;
  r.name = std::move(name);
  r.group = std::move(group);
  r.help = std::move(help);
  std::vector<std::string> keys;
  for (const auto& [k, v] : names) keys.push_back(k);
  r.bind = [field, names, keys, optName = r.name](CLI::App* c, S* s, const std::string& d) {
    return c
        ->add_option_function<std::string>(
            optName,
            [field, names, s](const std::string& v) {
              for (const auto& [k, e] : names)
                if (k == v) field(*s) = e;
            },
            d)
        ->check(CLI::IsMember(keys));
  };
  r.show = [field, names](const S& s) {
    for (const auto& [k, e] : names)
      if (e == field(const_cast<S&>(s))) return k;
    return std::string("?");
  };
  r.copy = [field](const S& from, S* to) { field(*to) = field(const_cast<S&>(from)); };
  return r;
}

// Registers every row on `c` bound to *parsed, each with its group, its unit
// and its default as shown in `defaults` (the struct or preset it starts from).
template <class S>
void addOptionRows(CLI::App* c, const OptionRows<S>& rows, S* parsed, const S& defaults) {
  for (const OptionRow<S>& r : rows) {
    std::string d = r.help;
    if (!r.unit.empty()) d += " [" + r.unit + "]";
    CLI::Option* o = r.bind(c, parsed, d);
    o->group(r.group);
    if (!(r.flag && r.negation.empty())) o->default_str(r.show(defaults));  // a lone flag: off
  }
}

// Was this row's option (or its negation) on `c`'s command line?
template <class S>
bool optionGiven(const CLI::App* c, const OptionRow<S>& r) {
  auto count = [c](const std::string& n) {
    const CLI::Option* o = n.empty() ? nullptr : c->get_option_no_throw(n);
    return o != nullptr ? o->count() : std::size_t{0};
  };
  return count(r.name) + count(r.negation) > 0;
}

// `out` (a preset's options) with each option the user gave on `c` set from
// `parsed`; the others keep the preset's values.
template <class S>
void copyGivenOptions(const CLI::App* c, const OptionRows<S>& rows, const S& parsed, S* out) {
  for (const OptionRow<S>& r : rows)
    if (optionGiven(c, r)) r.copy(parsed, out);
}

// Markdown tables of the rows, one per group (groups in order of first
// appearance): option, default (as in `defaults`), unit, help.
template <class S>
std::string optionRowsMarkdown(const OptionRows<S>& rows, const S& defaults) {
  std::vector<std::string> groups;
  for (const OptionRow<S>& r : rows)
    if (std::find(groups.begin(), groups.end(), r.group) == groups.end()) groups.push_back(r.group);
  std::string out;
  for (const std::string& group : groups) {
    out += "\n### " + group + "\n\n| option | default | unit | what it does |\n| --- | --- | --- | --- |\n";
    for (const OptionRow<S>& r : rows) {
      if (r.group != group) continue;
      std::string help = r.help;
      for (std::size_t p = 0; (p = help.find('|', p)) != std::string::npos; p += 2)
        help.replace(p, 1, "\\|");
      std::string names = "`" + r.name + "`";
      if (!r.negation.empty()) names += ", `" + r.negation + "`";
      const std::string def = r.flag && r.negation.empty() ? "" : r.show(defaults);
      out += "| " + names + " | " + def + " | " + r.unit + " | " + help + " |\n";
    }
  }
  return out;
}

}  // namespace hw::app
