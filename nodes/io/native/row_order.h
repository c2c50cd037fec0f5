#pragma once
// The rows a native image writer is given (nodes/io/native): each file row once, top to bottom, all of them
// before the file is closed, and none after. Both formats' libraries would otherwise write a file that looks whole.
#include <string>

namespace orogen {

class RowOrder {
 public:
  explicit RowOrder(int height) : height_(height) {}

  // Empty when rows [y0, y1) are the next ones; else why not.
  std::string check(int y0, int y1) const {
    if (closed_) return "the file is closed";
    if (y0 == next_ && y1 > y0 && y1 <= height_) return {};
    return "rows " + std::to_string(y0) + " to " + std::to_string(y1) + " written out of order (next is row " +
           std::to_string(next_) + " of " + std::to_string(height_) + ")";
  }
  void written(int y1) { next_ = y1; }

  // Marks the file closed. Empty when every row was written; else why the file is not whole.
  std::string close() {
    if (closed_) return "the file is closed";
    closed_ = true;
    if (next_ == height_) return {};
    return "closed after " + std::to_string(next_) + " of " + std::to_string(height_) + " rows";
  }
  bool closed() const { return closed_; }

 private:
  int height_;
  int next_ = 0;
  bool closed_ = false;
};

}  // namespace orogen
