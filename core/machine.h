#pragma once
// What a benchmark ran on: CPU model, core count, headless GL backend and
// GL_VENDOR/RENDERER/VERSION, llvmpipe thread setting, build type and git
// commit (recorded in every report).
#include <nlohmann/json.hpp>

#include <string>

namespace hw {

std::string cpuModel();
nlohmann::json machineInfo(const std::string& glRenderer, const std::string& glVersion);

}  // namespace hw
