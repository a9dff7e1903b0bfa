#include "assistive_tactile/serial_port.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>

namespace assistive_tactile
{
namespace
{
// Ports the signal handler writes the fail-safe bytes to. Lock-free atomics only: read from a
// signal handler. A port leaves the table before its fd is closed.
constexpr int kMaxFailSafePorts = 8;
std::atomic<int> g_fail_safe_fds[kMaxFailSafePorts] = { { -1 }, { -1 }, { -1 }, { -1 },
                                                       { -1 }, { -1 }, { -1 }, { -1 } };
uint8_t g_fail_safe_bytes[64];
std::atomic<size_t> g_fail_safe_len{ 0 };

void registerFailSafe(int fd)
{
  for (auto& slot : g_fail_safe_fds)
  {
    int expected = -1;
    if (slot.compare_exchange_strong(expected, fd))
      return;
  }
}

void unregisterFailSafe(int fd)
{
  for (auto& slot : g_fail_safe_fds)
  {
    int expected = fd;
    slot.compare_exchange_strong(expected, -1);
  }
}
}  // namespace

void setFailSafeBytes(const uint8_t* data, size_t len)
{
  len = std::min(len, sizeof(g_fail_safe_bytes));
  g_fail_safe_len = 0;
  std::memcpy(g_fail_safe_bytes, data, len);
  g_fail_safe_len = len;
}

void writeFailSafeBytes()
{
  const size_t len = g_fail_safe_len.load();
  if (len == 0)
    return;
  for (auto& slot : g_fail_safe_fds)
  {
    const int fd = slot.load();
    if (fd >= 0 && ::write(fd, g_fail_safe_bytes, len) < 0)
    {
      // nothing to do in a signal handler; the vest's watchdog is the last resort
    }
  }
}

bool baudToSpeed(int baud, unsigned int* speed)
{
  struct Entry
  {
    int baud;
    speed_t speed;
  };
  static const Entry table[] = { { 9600, B9600 },     { 19200, B19200 },   { 38400, B38400 },
                                 { 57600, B57600 },   { 115200, B115200 }, { 230400, B230400 },
                                 { 460800, B460800 }, { 921600, B921600 } };
  for (const Entry& e : table)
    if (e.baud == baud)
    {
      *speed = e.speed;
      return true;
    }
  return false;
}

SerialPort::~SerialPort()
{
  close();
}

void SerialPort::close()
{
  if (fd_ >= 0)
  {
    unregisterFailSafe(fd_);
    ::ioctl(fd_, TIOCNXCL);  // a pty slave held open elsewhere would otherwise stay exclusive
    ::close(fd_);
  }
  fd_ = -1;
}

void SerialPort::lost(const char* what, int err, std::string* error)
{
  if (error)
    *error = std::string(what) + ": " + std::strerror(err);
  close();
}

bool SerialPort::open(const std::string& path, int baud, std::string* error)
{
  close();
  unsigned int speed = 0;
  if (!baudToSpeed(baud, &speed))
  {
    if (error)
      *error = "unsupported baud rate " + std::to_string(baud);
    return false;
  }
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0)
  {
    const int e = errno;
    if (error)
      *error = "open " + path + ": " + std::strerror(e) +
               (e == EBUSY ? " (another process has it open exclusively)" : "");
    return false;
  }
  struct termios tio;
  if (!isatty(fd) || tcgetattr(fd, &tio) != 0)
  {
    if (error)
      *error = path + " is not a serial port";
    ::close(fd);
    return false;
  }
  // One writer only: a second bridge (or a tool that honours flock) must not share the port.
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
  {
    const int e = errno;
    if (error)
      *error = path + " is in use by another process (flock: " + std::strerror(e) + ")";
    ::close(fd);
    return false;
  }
  if (::ioctl(fd, TIOCEXCL) != 0)
  {
    if (error)
      *error = "exclusive open (TIOCEXCL) of " + path + ": " + std::strerror(errno);
    ::close(fd);
    return false;
  }
  cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | CRTSCTS | PARENB);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  cfsetispeed(&tio, static_cast<speed_t>(speed));
  cfsetospeed(&tio, static_cast<speed_t>(speed));
  if (tcsetattr(fd, TCSANOW, &tio) != 0)
  {
    if (error)
      *error = "configure " + path + ": " + std::strerror(errno);
    ::ioctl(fd, TIOCNXCL);
    ::close(fd);
    return false;
  }
  tcflush(fd, TCIOFLUSH);  // drop what the device said before we listened
  fd_ = fd;
  if (fail_safe_)
    registerFailSafe(fd_);
  return true;
}

bool SerialPort::checkAlive(std::string* error)
{
  if (fd_ < 0)
    return false;
  struct pollfd p;
  p.fd = fd_;
  p.events = POLLIN;
  p.revents = 0;
  const int r = ::poll(&p, 1, 0);
  if (r < 0 && errno != EINTR)
  {
    lost("poll", errno, error);
    return false;
  }
  if (r > 0 && (p.revents & (POLLHUP | POLLERR | POLLNVAL)))
  {
    lost("port hung up", EIO, error);
    return false;
  }
  return true;
}

ssize_t SerialPort::write(const uint8_t* data, size_t len, std::string* error)
{
  if (fd_ < 0)
    return -1;
  size_t done = 0;
  while (done < len)
  {
    const ssize_t n = ::write(fd_, data + done, len - done);
    if (n > 0)
    {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR)
      continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
      break;  // driver buffer full: caller keeps the rest
    lost("write", n < 0 ? errno : EIO, error);
    return -1;
  }
  return static_cast<ssize_t>(done);
}

ssize_t SerialPort::read(uint8_t* data, size_t len, std::string* error)
{
  if (fd_ < 0)
    return -1;
  for (;;)
  {
    const ssize_t n = ::read(fd_, data, len);
    if (n >= 0)
      return n;  // VMIN=0: 0 means nothing available (hang-up is seen by checkAlive)
    if (errno == EINTR)
      continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK)
      return 0;
    lost("read", errno, error);
    return -1;
  }
}

}  // namespace assistive_tactile
