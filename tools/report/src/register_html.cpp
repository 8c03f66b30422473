// Registers the HTML report with the runner while the program starts, for the programs that link
// cobra::run (the `cobra` tool, the applications' tests): their run folders get report.html.
#include "cobra/report/run_report.hpp"

// Kept by the linker through cobra::run's link option --undefined (tools/report/CMakeLists.txt).
extern "C" {
extern const int cobra_report_html_registered;
const int cobra_report_html_registered = (cobra::report::registerHtmlReport(), 1);
}
