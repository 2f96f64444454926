// The one exception type for bad input (files, options, budgets). It lives at
// the bottom of the tree so that every layer, host or pipeline, can throw it
// without depending on the scene: the CLI prints what() on one line and exits
// non-zero, and a library caller catches it. Its definition is public
// (include/rast/error.h), so that the installed API throws the same type.
#pragma once

#include "include/rast/error.h"
