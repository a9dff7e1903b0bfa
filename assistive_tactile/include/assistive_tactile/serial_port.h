#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace assistive_tactile
{
/// Maps a baud rate in bit/s to a termios speed constant; false when unsupported.
bool baudToSpeed(int baud, unsigned int* speed);

/**
 * A raw, non-blocking POSIX serial port (termios: 8N1, no flow control, no echo, VMIN=VTIME=0).
 * Works on USB-serial adapters and on pseudo-terminals. Every failure is reported, never thrown;
 * a port that hangs up is closed so the owner can reopen it.
 *
 * Opened exclusively: an advisory flock(LOCK_EX) (a second SerialPort / bridge on the same
 * device fails with "in use by another process") and TIOCEXCL (further open()s of the tty fail
 * with EBUSY; root is exempt from TIOCEXCL, not from the flock), so no second writer can inject
 * commands through a cooperating tool.
 */
class SerialPort
{
public:
  SerialPort() = default;
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  /// Opens and configures `path`; on failure returns false and sets `error`.
  bool open(const std::string& path, int baud, std::string* error);
  void close();
  bool isOpen() const { return fd_ >= 0; }
  int fd() const { return fd_; }

  /// Writes what the driver takes now. Returns bytes written (maybe 0 if the buffer is full),
  /// or -1 when the port is lost (then it is closed and `error` says why).
  ssize_t write(const uint8_t* data, size_t len, std::string* error);

  /// Reads what is available without blocking. Returns bytes read (0 = nothing), -1 when the
  /// port is lost (closed, `error` set).
  ssize_t read(uint8_t* data, size_t len, std::string* error);

  /// Polls for hang-up / error without blocking; closes the port and returns false when lost.
  bool checkAlive(std::string* error);

  /// While open, this port gets the fail-safe bytes from writeFailSafeBytes() (signal handler).
  void enableFailSafe(bool on) { fail_safe_ = on; }

private:
  void lost(const char* what, int err, std::string* error);
  int fd_ = -1;
  bool fail_safe_ = false;
};

/// Sets the bytes writeFailSafeBytes() sends (at most 64; e.g. the vest's all-off packets).
/// Call before any signal can use them.
void setFailSafeBytes(const uint8_t* data, size_t len);
/// Writes the fail-safe bytes to every open port that enabled it. Async-signal-safe (only
/// atomics and write()), for signal handlers.
void writeFailSafeBytes();

}  // namespace assistive_tactile
