// SPDX-License-Identifier: GPL-2.0-or-later
// The shipped closed-loop models this peer rebuilds, by their mbsc names.
#include <stdexcept>

#include "mechanism.hpp"

namespace simbench {

void build_four_bar(Mechanism&);
void build_four_bar_toggle(Mechanism&);
void build_slider_crank(Mechanism&);
void build_five_bar(Mechanism&);
void build_whitworth(Mechanism&);
void build_three_rrr(Mechanism&);
void build_parallelogram_chain(Mechanism&);

namespace {
struct Entry {
  const char* name;
  void (*build)(Mechanism&);
};
const Entry kModels[] = {
    {"four_bar", build_four_bar},   {"four_bar_toggle", build_four_bar_toggle}, {"slider_crank", build_slider_crank},
    {"five_bar", build_five_bar},   {"whitworth", build_whitworth},             {"three_rrr", build_three_rrr},
    {"parallelogram_chain", build_parallelogram_chain},
};
}  // namespace

std::unique_ptr<Mechanism> make_mechanism(const std::string& model) {
  for (const auto& e : kModels)
    if (model == e.name) {
      auto m = std::make_unique<Mechanism>();
      e.build(*m);
      return m;
    }
  throw std::runtime_error("no Simbody model '" + model + "' (known: four_bar, four_bar_toggle, slider_crank, five_bar, "
                           "whitworth, three_rrr, parallelogram_chain)");
}

std::vector<std::string> mechanism_names() {
  std::vector<std::string> out;
  for (const auto& e : kModels) out.emplace_back(e.name);
  return out;
}

}  // namespace simbench
