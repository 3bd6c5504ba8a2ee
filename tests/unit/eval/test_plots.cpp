#include <gtest/gtest.h>
TEST(P, Placeholder) {}
