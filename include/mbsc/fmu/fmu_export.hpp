// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc generate --fmi 2|3 [--fmi-kind me|cs|both]` (docs/fmi.md): NAME.fmu beside the
/// generated C++, a zip archive holding
///
///   modelDescription.xml              the variables (fmu/model_description.hpp)
///   binaries/<platform>/NAME.so       the model and its FMI functions, compiled here
///   sources/NAME.hpp, NAME.cpp        the generated model
///   sources/NAME_fmu.cpp              the glue (templates/fmu_glue.cpp.in)
///   sources/mbsc/{runtime,fmi}/...    the header-only runtime and FMI functions it includes
///   sources/buildDescription.xml      (FMI 3.0) how to build the sources elsewhere
///   documentation/licenses/LICENSE.txt  mbsc's licence and the exception that covers all of it
///
/// The start values are the state `mbsc run` would start from: the model's `initial`
/// values with the rest assembled from the constraints (through run's compiled, cached
/// full-state model), at the default parameters.
#include <iosfwd>
#include <vector>

#include "mbsc/driver/commands.hpp"

namespace mbsc::fmu {

struct FmuOptions {
  int version = 2;  // 2 or 3
  bool model_exchange = true, co_simulation = true;
};

/// The platform folder under binaries/ for this build of mbsc ("linux64" for FMI 2.0,
/// "x86_64-linux" for FMI 3.0 on x86-64 Linux), or "" where the standard names none.
std::string platform_folder(int version);

/// generate's extra_outputs for an FMU: builds NAME.fmu and appends it to `outputs`.
/// Returns 0, or the exit code with messages on `err`.
int add_fmu(const FmuOptions& options, const driver::GenerateArgs& args, const driver::GenerateArgs::Made& made,
            std::vector<driver::OutputFile>& outputs, std::ostream& err);

}  // namespace mbsc::fmu
