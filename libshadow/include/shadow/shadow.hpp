// SPDX-License-Identifier: GPL-3.0-or-later
/// @file shadow.hpp
/// @brief Everything of libshadow's public API in one include: the compute component's headers
/// (libshadow/compute/include) and the io component's (libshadow/io/include).
#pragma once

#include <shadow/area_lights.hpp>
#include <shadow/blinn.hpp>
#include <shadow/energyplus.hpp>
#include <shadow/epw.hpp>
#include <shadow/error.hpp>
#include <shadow/generators.hpp>
#include <shadow/input_file.hpp>
#include <shadow/irradiance.hpp>
#include <shadow/irradiance_output.hpp>
#include <shadow/lighting.hpp>
#include <shadow/material.hpp>
#include <shadow/output.hpp>
#include <shadow/radiosity.hpp>
#include <shadow/radiosity_output.hpp>
#include <shadow/scene.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/series.hpp>
#include <shadow/series_files.hpp>
#include <shadow/series_job.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun.hpp>
#include <shadow/sun_hours.hpp>
#include <shadow/validation.hpp>
#include <shadow/version.hpp>
#include <shadow/view.hpp>
#include <shadow/weather.hpp>
