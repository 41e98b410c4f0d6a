// Entry point shared by every CppUTest executable.
#include "CppUTest/CommandLineTestRunner.h"
#include "CppUTest/MemoryLeakWarningPlugin.h"

int main(int argc, char** argv) {
  // Link and board tests allocate from a reader thread as well as the test's: the leak
  // detector's bookkeeping is not safe against that unless its new/delete take a lock.
  MemoryLeakWarningPlugin::turnOnThreadSafeNewDeleteOverloads();
  return CommandLineTestRunner::RunAllTests(argc, argv);
}
