// SPDX-License-Identifier: GPL-2.0-or-later
#include "initial_states.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace simbench {

std::vector<InitialState> read_initial_states(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<InitialState> out;
  std::string line;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    InitialState st;
    if (!(fields >> st.model)) continue;
    for (std::string f; fields >> f;) {
      const auto at = f.find_first_of("=~");
      const std::string where = path + ":" + std::to_string(lineno) + ": ";
      if (at == std::string::npos || at == 0 || at + 1 == f.size())
        throw std::runtime_error(where + "expected name=value or name~value, got '" + f + "'");
      const std::string value = f.substr(at + 1);
      char* end = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      if (*end != '\0') throw std::runtime_error(where + "'" + value + "' is not a number");
      (f[at] == '=' ? st.given : st.guess).emplace_back(f.substr(0, at), v);
    }
    out.push_back(std::move(st));
  }
  return out;
}

InitialState find_initial_state(const std::string& path, const std::string& model) {
  for (auto& st : read_initial_states(path))
    if (st.model == model) return st;
  throw std::runtime_error(path + ": no initial state for model '" + model + "'");
}

}  // namespace simbench
