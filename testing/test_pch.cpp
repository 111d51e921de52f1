// Owns the tests' precompiled header (tagbench_test_pch in CMakeLists.txt); nothing of its own.
