// Placeholder: implemented in the loader change.
#include "scene/loader.hpp"
