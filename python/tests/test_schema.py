"""epaphe.schema from `epaphe-run --print-parameters=xml`: types, defaults, an enumeration's values,
a range, a "*" list (any body name), the nearest valid key of a misspelt one; the keys agree with the
human-readable --print-parameters listing."""
import re
import subprocess
import unittest

import support
from epaphe.schema import Schema


class FromEpapheRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.schema = Schema(support.RUN)

    def test_types_and_defaults(self):
        p = self.schema.param("Time->Time step")
        self.assertEqual(p.type, "double")
        self.assertGreater(float(p.default), 0.0)
        self.assertTrue(p.doc)
        self.assertEqual(self.schema.param("Run->Threads").type, "int")
        self.assertEqual(self.schema.param("Bodies->Bar->Mesh->Elements").type, "Array(int)")
        self.assertEqual(self.schema.lookup("Contact->Method")[1], "string")

    def test_enumeration(self):
        p = self.schema.param("Bodies->Bar->Mesh->Type")
        for v in ("Box", "Ring segment", "Blade", "Casing", "Sphere", "CalculiX"):
            self.assertIn(v, p.values)
        self.assertEqual(p.default, "Box")

    def test_range(self):
        p = self.schema.param("Bodies->Ball->Mesh->Pole grading")  # [0.02, 1] in its docString
        self.assertEqual((p.minimum, p.maximum), (0.02, 1.0))
        p = self.schema.param("Run->Threads")
        self.assertEqual((p.minimum, p.maximum), (0, 1024))
        self.assertIsNone(self.schema.param("Bodies->Ball->Mesh->Stagger").maximum)  # unbounded: inf

    def test_any_name(self):
        p = self.schema.param("Bodies->Anything at all->Initial velocity")
        self.assertEqual(p.path, ("Bodies", "*", "Initial velocity"))
        self.assertIn(("Bodies", "*"), self.schema.lists)
        self.assertIsNone(self.schema.param("Bodies->Initial velocity"))

    def test_suggestion(self):
        self.assertEqual(self.schema.close("Time->Time stpe"), "Time->Time step")
        self.assertEqual(self.schema.close("Bodies->Bar->Inital velocity"), "Bodies->Bar->Initial velocity")
        self.assertIsNone(self.schema.param("Time->Time stpe"))

    def test_agrees_with_the_listing(self):
        """Every 'name (type, default ...)' of the human-readable listing is a parameter of the schema
        with that type (the listing is indented two spaces a level, lists in [brackets])."""
        text = subprocess.run([support.RUN, "--print-parameters"], capture_output=True, text=True, check=True).stdout
        path, seen = [], 0
        for line in text.splitlines():
            m = re.match(r"^( *)\[(.+?)\]", line)
            if m:
                path = path[: len(m.group(1)) // 2] + ["*" if m.group(2) == "<any name>" else m.group(2)]
                continue
            m = re.match(r"^( *)(\S.*?) \((string|int|double|bool|Array\((?:string|int|double)\)), default", line)
            if m and len(m.group(1)) // 2 <= len(path):
                sp = tuple(path[: len(m.group(1)) // 2]) + (m.group(2),)
                self.assertIn(sp, self.schema.params, sp)
                self.assertEqual(self.schema.params[sp].type, m.group(3), sp)
                seen += 1
        self.assertEqual(seen, len(self.schema.params))


if __name__ == "__main__":
    unittest.main()
