"""The README's examples run as a user would paste them, and print what the README says they
print: the C++ quick start compiled against the built core and run, the Python quick start
run (on the TUM frame in ../shared/data, skipped with a message when it is absent), and the
command-line quick start run line by line in a scratch folder. A README that drifts from the
code fails here. Run by ctest (python_readme_examples)."""

import os
import re
import shlex
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
README = os.path.join(ROOT, "README.md")


def blocks(language, text):
    return re.findall(r"```" + language + r"\n(.*?)```", text, re.S)


def section(text, title):
    start = text.index("## " + title)
    end = text.find("\n## ", start + 1)
    return text[start:end if end > 0 else len(text)]


class ReadmeExamples(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(README) as f:
            cls.readme = f.read()

    def test_cpp_quick_start_compiles_runs_and_prints_what_it_says(self):
        text = section(self.readme, "Quick start: C++")
        (code,) = blocks("cpp", text)
        sentence = re.search(r"It prints (.*?)\.\s", text, re.S).group(1)
        promised = re.findall(r"`([^`]+)`", sentence)
        self.assertTrue(promised, "the README says what the example prints")
        with tempfile.TemporaryDirectory() as tmp:
            source = os.path.join(tmp, "example.cpp")
            with open(source, "w") as f:
                f.write(code)
            binary = os.path.join(tmp, "example")
            core = os.environ["HOPE_CORE_LIBRARY"]
            command = (["c++", "-std=c++17", "-Wall", "-Wextra", "-Werror", source, "-o", binary]
                       + shlex.split(os.environ["HOPE_EXAMPLE_CXXFLAGS"])
                       + [core, "-Wl,-rpath," + os.path.dirname(core)])
            # The compiler runs without a sanitizer's preloaded runtime (scripts/sanitize.sh
            # preloads it into the Python tests); the example runs with it, as the core needs.
            compile_env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
            built = subprocess.run(command, capture_output=True, text=True, env=compile_env)
            self.assertEqual(built.returncode, 0, built.stderr[-3000:])
            run = subprocess.run([binary], capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 0, run.stderr)
        lines = run.stdout.splitlines()
        for line in promised:
            self.assertIn(line, lines, "the README promises this line")

    def test_python_quick_start_prints_what_it_says(self):
        text = section(self.readme, "Quick start: Python")
        (code,) = blocks("python", text)
        frame = re.search(r'"(\.\./shared/data/[^"]+)"', code).group(1)
        if not os.path.exists(os.path.join(ROOT, frame)):
            self.skipTest("no %s (../shared/data absent): Python quick start skipped" % frame)
        promised = re.search(r"# first: (.+)", code).group(1).strip()
        run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                             text=True, timeout=120)
        self.assertEqual(run.returncode, 0, run.stderr[-3000:])
        self.assertEqual(run.stdout.splitlines()[0], promised)

    def test_command_line_quick_start_runs(self):
        text = section(self.readme, "Quick start: command line")
        (script,) = blocks("sh", text)
        commands = [line for line in script.splitlines()
                    if line.strip() and not line.lstrip().startswith("#")]
        # Continuation lines joined; the PATH line replaced by the tools of this build.
        joined = []
        for line in commands:
            if joined and joined[-1].endswith("\\"):
                joined[-1] = joined[-1][:-1] + " " + line.strip()
            else:
                joined.append(line)
        bin_dir = os.path.dirname(os.environ["HOPE_EXTRACT_BIN"])
        env = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ["PATH"])
        ran = 0
        with tempfile.TemporaryDirectory() as tmp:
            # ../shared/data as seen from the repository root, from the scratch folder.
            work = os.path.join(tmp, "main")
            os.mkdir(work)
            shared = os.path.join(os.path.dirname(ROOT), "shared")
            if os.path.exists(shared):
                os.symlink(shared, os.path.join(tmp, "shared"))
            for command in joined:
                if command.startswith("export PATH="):
                    continue
                if "../shared/data" in command and not os.path.exists(shared):
                    print("skipped (no ../shared/data): " + command)
                    continue
                run = subprocess.run(["bash", "-c", command], cwd=work, env=env,
                                     capture_output=True, text=True, timeout=600)
                self.assertEqual(run.returncode, 0, command + "\n" + run.stderr[-3000:])
                ran += 1
        self.assertGreaterEqual(ran, 4, "the demo room and LiDAR commands need no data")


if __name__ == "__main__":
    unittest.main()
