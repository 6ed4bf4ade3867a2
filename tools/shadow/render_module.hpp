// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow render` runs in a module of its own, loaded only when a picture is asked for: VTK's
// OpenGL rendering, X11, cairo and their 40-odd libraries cost every other run of `shadow` some
// 20 ms of loading and start-up before main (docs/benchmarks.md, "The render module").
#pragma once

#include "render_command.hpp"

/// The module's file name, in LIBSHADOW_RENDER_MODULE_DIR (relative to the `shadow` program's
/// own folder, the same in the build tree and an install) or else wherever dlopen looks.
inline constexpr const char* kRenderModuleFile = "shadow_render_module.so";

/// What the module exports (render_command.cpp): its RenderArgs' size, a check that the program
/// and the module were built together, and the entry point, run_render with its RenderError
/// reported as `shadow render` reports it (exit 3); other errors (InputError, OutputError,
/// bad_alloc) are thrown on to the program, whose handlers give them their exit codes.
inline constexpr const char* kRenderModuleArgsSize = "shadow_render_module_args_size";
inline constexpr const char* kRenderModuleEntry = "shadow_render_module_run";
extern "C" {
using RenderModuleArgsSize = std::size_t (*)();
using RenderModuleEntry = int (*)(const RenderArgs& args, int argc, char** argv);
}

/// Loads the render module and runs `shadow render` in it. @throws std::runtime_error naming the
/// module and what went wrong when it cannot be loaded; whatever the module throws.
int run_render_module(const RenderArgs& args, int argc, char** argv);
