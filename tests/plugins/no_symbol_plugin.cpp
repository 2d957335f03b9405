// A shared library that is not a sphforge plugin (no exported plugin symbols).
extern "C" int sphforge_test_unrelated_function() { return 42; }
