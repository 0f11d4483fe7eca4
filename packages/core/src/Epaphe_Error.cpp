#include "Epaphe_Error.hpp"
// Anchors the vtable of epaphe::Error in the core library.
