#!/usr/bin/python3
"""Every script in scripts/ with a `#!` line is executable, in git (mode 100755, what a
fresh clone gets) and in the working tree: README and docs call them as `scripts/<name>.py`, and
five of them were committed without the bit until session 53 (`Permission denied`, exit 126)."""
import os
import subprocess
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


@unittest.skipUnless(os.path.isdir(os.path.join(ROOT, ".git")), "not a git checkout: no modes to read")
class ScriptModes(unittest.TestCase):
    def test_every_script_with_a_shebang_is_executable(self):
        listing = subprocess.run(["git", "ls-files", "-s", "scripts"], cwd=ROOT, check=True,
                                 capture_output=True, text=True).stdout
        checked, not_executable = 0, []
        for line in listing.splitlines():
            mode, _, _, path = line.split(maxsplit=3)
            with open(os.path.join(ROOT, path), "rb") as f:
                if f.read(2) != b"#!":
                    continue
            checked += 1
            if mode != "100755" or not os.access(os.path.join(ROOT, path), os.X_OK):
                not_executable.append(f"{path} (git mode {mode})")
        self.assertGreater(checked, 5)
        self.assertEqual(not_executable, [], "scripts with a #! line that are not executable")


if __name__ == "__main__":
    unittest.main()
