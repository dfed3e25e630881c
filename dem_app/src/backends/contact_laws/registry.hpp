// The contact laws by name: the values of coupling.<backend>.contact_law (rve_schema.cpp), the
// law of an RVE (native::ContactLaw's kind: the index of its law in AllLaws) and what
// `dem_app --list-backends --long` prints. The kernels (native contact_kernel*.cpp, measures.cpp)
// are templates over the law and reach it through visit_law.
// Adding a law: its one header here (frict.hpp shows what a law defines), one entry in
// AllLaws below and its enumerator in native::ContactLawKind (docs/add_a_contact_law.md).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "backends/contact_laws/frict.hpp"
#include "backends/contact_laws/frict_visco.hpp"

namespace mpmdem::dem::laws {

template <class... L>
struct LawList {};
// Every law, in the order of their ids (stored in binary states and checkpoints: append only).
using AllLaws = LawList<Frict, FrictVisco>;

struct LawInfo {
  const char* name;     // the value of coupling.<backend>.contact_law
  const char* summary;  // one line
  bool viscous;         // Law::kViscous
};

namespace detail {
template <class... L>
constexpr std::array<LawInfo, sizeof...(L)> infos(LawList<L...>) {
  return {{{L::kName, L::kSummary, L::kViscous}...}};
}
template <class F, class First, class... Rest>
decltype(auto) visit(int id, F&& f, LawList<First, Rest...>) {
  if constexpr (sizeof...(Rest) == 0) {
    return f(First{});
  } else {
    if (id <= 0) return f(First{});
    return visit(id - 1, std::forward<F>(f), LawList<Rest...>{});
  }
}
}  // namespace detail

// The laws' names, summaries and traits, by id.
inline constexpr auto kLaws = detail::infos(AllLaws{});

// f(Law{}) for the law of that id (ids past the end: the last law; ids are checked where they
// are read). Every law's f must return the same type.
template <class F>
decltype(auto) visit_law(int id, F&& f) {
  return detail::visit(id, std::forward<F>(f), AllLaws{});
}

// The laws' names, in id order (the values coupling.<backend>.contact_law accepts).
inline std::vector<std::string> law_names() {
  std::vector<std::string> names;
  for (const LawInfo& l : kLaws) names.emplace_back(l.name);
  return names;
}

// The id of the law of that name, or -1.
inline int find_law(const std::string& name) {
  for (std::size_t i = 0; i < kLaws.size(); ++i) {
    if (name == kLaws[i].name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace mpmdem::dem::laws
