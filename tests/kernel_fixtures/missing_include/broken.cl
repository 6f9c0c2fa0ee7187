/* test_kernel_sources: both kernel assemblers must stop at line 3 naming this file. */
#include "present.h"
#include "absent.h"
