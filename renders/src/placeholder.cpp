#include "invfem/core/types.hpp"
