// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/emit/python_module_names.hpp"

#include <algorithm>
#include <iterator>

namespace mbsc::emit {

namespace {

/// Python 3's standard-library modules and packages (top level, public names only: a
/// model name cannot start with an underscore and a capital, and `_x` names are not
/// imported by users), kept in byte order for the binary search below.
const char* const kStandardModules[] = {
    "abc",          "aifc",          "antigravity",  "argparse",     "array",        "ast",          "asynchat",
    "asyncio",      "asyncore",      "atexit",       "audioop",      "base64",       "bdb",          "binascii",
    "binhex",       "bisect",        "builtins",     "bz2",          "cProfile",     "calendar",     "cgi",
    "cgitb",        "chunk",         "cmath",        "cmd",          "code",         "codecs",       "codeop",
    "collections",  "colorsys",      "compileall",   "concurrent",   "configparser", "contextlib",   "contextvars",
    "copy",         "copyreg",       "crypt",        "csv",          "ctypes",       "curses",       "dataclasses",
    "datetime",     "dbm",           "decimal",      "difflib",      "dis",          "distutils",    "doctest",
    "email",        "encodings",     "ensurepip",    "enum",         "errno",        "faulthandler", "fcntl",
    "filecmp",      "fileinput",     "fnmatch",      "formatter",    "fractions",    "ftplib",       "functools",
    "gc",           "genericpath",   "getopt",       "getpass",      "gettext",      "glob",         "graphlib",
    "grp",          "gzip",          "hashlib",      "heapq",        "hmac",         "html",         "http",
    "idlelib",      "imaplib",       "imghdr",       "imp",          "importlib",    "inspect",      "io",
    "ipaddress",    "itertools",     "json",         "keyword",      "lib2to3",      "linecache",    "locale",
    "logging",      "lzma",          "macpath",      "mailbox",      "mailcap",      "marshal",      "math",
    "mimetypes",    "mmap",          "modulefinder", "msilib",       "msvcrt",       "multiprocessing", "netrc",
    "nis",          "nntplib",       "nt",           "ntpath",       "nturl2path",   "numbers",      "opcode",
    "operator",     "optparse",      "os",           "ossaudiodev",  "parser",       "pathlib",      "pdb",
    "pickle",       "pickletools",   "pipes",        "pkgutil",      "platform",     "plistlib",     "poplib",
    "posix",        "posixpath",     "pprint",       "profile",      "pstats",       "pty",          "pwd",
    "py_compile",   "pyclbr",        "pydoc",        "pydoc_data",   "pyexpat",      "queue",        "quopri",
    "random",       "re",            "readline",     "reprlib",      "resource",     "rlcompleter",  "runpy",
    "sched",        "secrets",       "select",       "selectors",    "shelve",       "shlex",        "shutil",
    "signal",       "site",          "smtpd",        "smtplib",      "sndhdr",       "socket",       "socketserver",
    "spwd",         "sqlite3",       "sre_compile",  "sre_constants", "sre_parse",   "ssl",          "stat",
    "statistics",   "string",        "stringprep",   "struct",       "subprocess",   "sunau",        "symbol",
    "symtable",     "sys",           "sysconfig",    "syslog",       "tabnanny",     "tarfile",      "telnetlib",
    "tempfile",     "termios",       "textwrap",     "this",         "threading",    "time",         "timeit",
    "tkinter",      "token",         "tokenize",     "tomllib",      "trace",        "traceback",    "tracemalloc",
    "tty",          "turtle",        "turtledemo",   "types",        "typing",       "unicodedata",  "unittest",
    "urllib",       "uu",            "uuid",         "venv",         "warnings",     "wave",         "weakref",
    "webbrowser",   "winreg",        "winsound",     "wsgiref",      "xdrlib",       "xml",          "xmlrpc",
    "zipapp",       "zipfile",       "zipimport",    "zlib",         "zoneinfo",
};

/// What the generated module imports besides the standard library (templates/model.py.in).
const char* const kImportedPackages[] = {"numpy"};

bool less(const char* a, const std::string& b) { return b.compare(a) > 0; }

}  // namespace

bool is_python_module_name(const std::string& name) {
  const auto end = std::end(kStandardModules);
  const auto it = std::lower_bound(std::begin(kStandardModules), end, name, less);
  if (it != end && name == *it) return true;
  return std::find(std::begin(kImportedPackages), std::end(kImportedPackages), name) != std::end(kImportedPackages);
}

}  // namespace mbsc::emit
