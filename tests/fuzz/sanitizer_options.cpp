// Sanitizer defaults compiled into every fuzz target, so that a target run by hand behaves as
// under scripts/fuzz.sh: UndefinedBehaviorSanitizer stops at its first report, with a stack
// trace. UBSAN_OPTIONS adds to these and wins where they differ.
extern "C" const char* __ubsan_default_options() { return "halt_on_error=1:print_stacktrace=1"; }
