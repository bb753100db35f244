#include "invfem/collisions/implicit_surface.hpp"
