// Placeholder: filled by the reader work of issue 7.
#include <gtest/gtest.h>
