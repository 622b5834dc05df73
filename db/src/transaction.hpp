#pragma once

// A transaction on a connection of either backend, the same rules for both: begun when made,
// committed by commit(), rolled back when it goes without one (an exception on the way out).

namespace tocd::db::detail {

/// `Connection::exec(sql)` runs a statement and throws on failure; `rollback_quietly(c)`,
/// found beside the connection type, rolls back without throwing, as a destructor must.
template <class Connection>
class BasicTransaction {
 public:
  BasicTransaction(const Connection& c, const char* begin) : c_(c) { c_.exec(begin); }
  ~BasicTransaction() {
    if (open_) rollback_quietly(c_);
  }
  BasicTransaction(const BasicTransaction&) = delete;
  BasicTransaction& operator=(const BasicTransaction&) = delete;

  void commit() {
    c_.exec("COMMIT");
    open_ = false;
  }

 private:
  const Connection& c_;
  bool open_ = true;
};

}  // namespace tocd::db::detail
