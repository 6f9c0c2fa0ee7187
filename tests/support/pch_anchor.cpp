// The one source of decalcomp_test_pch (tests/CMakeLists.txt): it exists so that the test
// executables' shared precompiled headers have a target to be built by.
