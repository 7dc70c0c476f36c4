// Placeholder: implemented in the camera-path change.
#include "scene/camera_path.hpp"
