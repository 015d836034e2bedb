// Compiled only to build the tests' precompiled header (CMakeLists.txt, nf_test_pch).
