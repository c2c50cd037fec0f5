#include "editor/ui/theme.h"
