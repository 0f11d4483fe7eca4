#include "Epaphe_Runtime.hpp"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  rt.initializeKokkos(2);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
