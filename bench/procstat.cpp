// Runs one command and reports what it cost, as one JSON line on stdout:
//   procstat [--stdout FILE] [--timeout SEC] -- CMD [ARGS...]
//   {"status":0,"signal":0,"timedOut":false,"wallMs":..,"userMs":..,"sysMs":..,"maxRssKiB":..}
// wallMs runs from just before fork() to the return of wait4(); maxRssKiB is the child's
// peak resident set (ru_maxrss of wait4). The child's stdout goes to FILE (default
// /dev/null) and its stderr to /dev/null. --timeout kills the child with SIGKILL.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

static volatile pid_t g_child = 0;
static volatile sig_atomic_t g_timedOut = 0;

static void onAlarm(int) {
  g_timedOut = 1;
  if (g_child > 0) kill(g_child, SIGKILL);
}

static double nowMs() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static double tvMs(const timeval& tv) { return tv.tv_sec * 1e3 + tv.tv_usec / 1e3; }

int main(int argc, char** argv) {
  const char* out = "/dev/null";
  double timeout = 0;
  int i = 1;
  for (; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--stdout") && i + 1 < argc)
      out = argv[++i];
    else if (!std::strcmp(argv[i], "--timeout") && i + 1 < argc)
      timeout = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--")) {
      ++i;
      break;
    } else
      break;
  }
  if (i >= argc) {
    std::fprintf(stderr, "usage: procstat [--stdout FILE] [--timeout SEC] -- CMD [ARGS...]\n");
    return 2;
  }
  int fdOut = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  int fdNull = open("/dev/null", O_WRONLY);
  if (fdOut < 0 || fdNull < 0) {
    std::perror(out);
    return 2;
  }

  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = onAlarm;  // no SA_RESTART: wait4 returns EINTR and is retried
  sigaction(SIGALRM, &sa, nullptr);

  double t0 = nowMs();
  pid_t pid = fork();
  if (pid < 0) {
    std::perror("fork");
    return 2;
  }
  if (pid == 0) {
    dup2(fdOut, 1);
    dup2(fdNull, 2);
    execvp(argv[i], argv + i);
    _exit(127);
  }
  g_child = pid;
  if (timeout > 0) {
    itimerval it{};
    it.it_value.tv_sec = time_t(timeout);
    it.it_value.tv_usec = suseconds_t((timeout - double(time_t(timeout))) * 1e6);
    setitimer(ITIMER_REAL, &it, nullptr);
  }
  int st = 0;
  rusage ru{};
  while (wait4(pid, &st, 0, &ru) < 0) {
    if (errno != EINTR) {
      std::perror("wait4");
      return 2;
    }
  }
  double t1 = nowMs();
  std::printf(
      "{\"status\":%d,\"signal\":%d,\"timedOut\":%s,\"wallMs\":%.3f,\"userMs\":%.3f,\"sysMs\":%.3f,\"maxRssKiB\":%ld}"
      "\n",
      WIFEXITED(st) ? WEXITSTATUS(st) : -1, WIFSIGNALED(st) ? WTERMSIG(st) : 0, g_timedOut ? "true" : "false", t1 - t0,
      tvMs(ru.ru_utime), tvMs(ru.ru_stime), ru.ru_maxrss);
  return 0;
}
