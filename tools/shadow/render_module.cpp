// SPDX-License-Identifier: GPL-3.0-or-later
// Loads the render module (render_module.hpp) when `shadow render` is run.
#include "render_module.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>

#ifndef LIBSHADOW_RENDER_MODULE_DIR
#define LIBSHADOW_RENDER_MODULE_DIR "."
#endif

int run_render_module(const RenderArgs& args, int argc, char** argv) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  const fs::path beside = error ? fs::path() : self.parent_path() / LIBSHADOW_RENDER_MODULE_DIR / kRenderModuleFile;
  // Beside the program first (its build tree or its install); then dlopen's own search.
  void* module = nullptr;
  std::string why;
  if (!beside.empty() && fs::exists(beside, error)) {
    module = dlopen(beside.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr) why = dlerror();
  }
  if (module == nullptr) {
    module = dlopen(kRenderModuleFile, RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr && why.empty()) why = dlerror();
  }
  // Under a memory limit the module's segments may not map: that is the run out of memory
  // (exit 6 from the program's handler), not a broken install.
  if (module == nullptr && (why.find("Cannot allocate memory") != std::string::npos ||
                            why.find("failed to map segment") != std::string::npos))
    throw std::bad_alloc();
  if (module == nullptr)
    throw std::runtime_error("`shadow render` cannot load its module " + std::string(kRenderModuleFile) + " (looked in " +
                             (beside.empty() ? std::string("dlopen's path") : beside.parent_path().string()) +
                             " and dlopen's path): " + why);
  // Kept loaded: VTK's registrations and the picture's objects live until the program ends.
  const auto args_size = reinterpret_cast<RenderModuleArgsSize>(dlsym(module, kRenderModuleArgsSize));
  const auto entry = reinterpret_cast<RenderModuleEntry>(dlsym(module, kRenderModuleEntry));
  if (args_size == nullptr || entry == nullptr || args_size() != sizeof(RenderArgs))
    throw std::runtime_error("`shadow render`'s module " + std::string(kRenderModuleFile) +
                             " is not the one built with this program (rebuild or reinstall libshadow)");
  return entry(args, argc, argv);
}
