#pragma once
// libpng's error handlers for the native PNG reader and writer. libpng reports errors by longjmp to the setjmp of
// the calling function: every function that calls into libpng sets it, and holds nothing with a destructor across
// the calls. The error pointer given to png_create_*_struct is a std::string that receives the message.
#include <png.h>

#include <string>

namespace orogen::png_errors {

[[noreturn]] inline void on_error(png_structp png, png_const_charp message) {
  auto* error = static_cast<std::string*>(png_get_error_ptr(png));
  if (error) *error = message ? message : "libpng error";
  png_longjmp(png, 1);
}
inline void on_warning(png_structp, png_const_charp) {}

}  // namespace orogen::png_errors
