// LeakSanitizer suppressions for leaks inside third-party libraries that maxslice cannot
// free (sanitizer builds only; ignored otherwise). Checked by reading the same file 1 and 5
// times (docs/decisions/0002-import.md):
// - Open CASCADE: STEPControl_Controller::Init / IGESControl_Controller::Init register
//   static parameters and editors once per process and never free them (constant, ~3 KB).
// - lib3mf 1.8.1 with libzip 1.7: about 160 bytes per zip entry opened are never freed
//   inside zip_fopen_index (about 0.5 KB per 3MF file read).
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libTKernel.so\n"
           "leak:libTKXSBase.so\n"
           "leak:libTKSTEP.so\n"
           "leak:libTKIGES.so\n"
           "leak:libzip.so\n";
}
