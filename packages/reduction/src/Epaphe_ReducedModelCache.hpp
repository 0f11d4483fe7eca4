#pragma once
// A reduced model cached in HDF5 and reused when the model and reduction parameters are unchanged.
// The key is a hash of everything the reduction depends on (the caller's canonical text of the
// model and reduction parameters, and the Epaphe version).
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SpeedParametricModel.hpp"

#include <string>

namespace epaphe {

/// Stable 64-bit FNV-1a hash of `text`, as 16 hex digits.
std::string contentKey(const std::string& text);

/// Writes `model` to the HDF5 file `path` with its cache key `key` (the file replaced atomically).
void saveReducedModel(const ReducedModel& model, const std::string& path, const std::string& key);

/// True and fills `out` when `path` holds a reduced model with this key; false when the file is
/// absent or holds another key. A file that exists but cannot be read raises an error.
bool loadReducedModel(const std::string& path, const std::string& key, ReducedModel& out);

/// The same for the parametric model of a rotating body over a speed range.
void saveParametricModel(const SpeedParametricModel& model, const std::string& path, const std::string& key);
/// True and fills `out` when `path` holds a parametric model with this key; false when the file is absent
/// or holds another key. A file that exists but cannot be read raises an error.
bool loadParametricModel(const std::string& path, const std::string& key, SpeedParametricModel& out);

}  // namespace epaphe
