"""epaphe.deck: a deck read with line numbers, values (with the schema's defaults), overrides that
create what is missing (types from the given type, else the schema, else the deck, else string),
written and read back."""
import os
import unittest

import support
from epaphe.deck import Deck, deck_value, read_deck, variant
from epaphe.errors import EpapheError, UnknownName
from epaphe.schema import Schema

# a two-parameter schema, in the form epaphe-run --print-parameters=xml prints
SCHEMA = """<ParameterList name="Epaphe">
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="1.0e-07" docString="s"/>
    <ParameterList name="Damping">
      <Parameter name="Rayleigh alpha" type="double" value="0" docString="1/s"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Bodies"><ParameterList name="*">
    <Parameter name="Initial velocity" type="Array(double)" value="{0, 0, 0}" docString="m/s"/>
  </ParameterList></ParameterList>
</ParameterList>"""


def line_of(path, text):
    with open(path) as fh:
        return next(i for i, line in enumerate(fh, 1) if text in line)


class DeckRoundTrip(unittest.TestCase):
    def setUp(self):
        self.dir = support.workdir("deck")
        self.deck = read_deck(support.BAR)
        self.schema = Schema.from_xml(SCHEMA)

    def test_lines(self):
        for key, text in (
            ("Time->Time step", 'name="Time step"'),
            ("Bodies->Bar->Mesh", 'name="Mesh"'),
            ("Bodies->Bar->Material->Young's modulus", 'name="Young\'s modulus"'),
        ):
            self.assertEqual(self.deck.line(key), line_of(support.BAR, text), key)
        self.assertIsNone(self.deck.line("Time->No such key"))

    def test_values(self):
        self.assertEqual(self.deck.get("Time->Time step"), "1e-7")
        self.assertEqual(self.deck.get("Bodies->Bar->Material->Young's modulus"), "2e11")  # a quote in the name
        self.assertEqual(self.deck.sublists("Bodies"), ["Bar"])
        self.assertIsNone(self.deck.get("Time->Damping->Rayleigh alpha"))
        self.assertEqual(self.deck.get("Time->Damping->Rayleigh alpha", self.schema), "0")  # the default
        self.assertEqual(deck_value(self.deck, "Bodies->Bar->Mesh->Lengths"), [0.2, 0.02, 0.02])
        self.assertEqual(deck_value(support.BAR, "Contact->Method"), "Lagrange")
        with self.assertRaisesRegex(UnknownName, "no parameter 'Time->Time stpe'.*Time step"):
            deck_value(self.deck, "Time->Time stpe")

    def test_override_write_read(self):
        over = {
            "Time->Time step": "5e-8",  # replaced, type kept
            "Time->Damping->Rayleigh alpha": "10",  # list and parameter created, type from the schema
            "Output->Every": ("4", "int"),  # explicit type
            "Run->Note": "a string",  # unknown to the schema: string
            "Bodies->Bar->Initial velocity": "{50, 0, 0}",
        }
        path = self.deck.override(over, self.schema).write(os.path.join(self.dir, "variant.xml"))
        back = read_deck(path)
        for key, value in over.items():
            self.assertEqual(back.get(key), value[0] if isinstance(value, tuple) else value, key)
        types = {
            k: back.node("->".join(k.split("->")[:-1])).find(f"Parameter[@name='{k.split('->')[-1]}']").get("type")
            for k in over
        }
        self.assertEqual(
            types,
            {
                "Time->Time step": "double",
                "Time->Damping->Rayleigh alpha": "double",
                "Output->Every": "int",
                "Run->Note": "string",
                "Bodies->Bar->Initial velocity": "Array(double)",
            },
        )
        # everything else as it was, in the same order
        before = {k: v for k, v in self.deck.parameters().items() if k not in over}
        after = {k: v for k, v in back.parameters().items() if k not in over}
        self.assertEqual(list(before.items()), list(after.items()))
        # the line numbers are those of the file written
        self.assertEqual(back.line("Time->Time step"), line_of(path, 'name="Time step"'))
        # the original is untouched
        self.assertEqual(self.deck.get("Time->Time step"), "1e-7")

    def test_variant(self):
        out = variant(support.BAR, os.path.join(self.dir, "v.xml"), {"Time->End time": ("1e-5", "double")})
        self.assertEqual(Deck(out).get("Time->End time"), "1e-5")
        with open(out) as fh:
            self.assertEqual(Deck(out).text(), Deck(text=fh.read()).text())  # text round trip

    def test_errors(self):
        bad = os.path.join(self.dir, "bad.xml")
        with open(bad, "w") as fh:
            fh.write('<ParameterList name="Epaphe">\n  <Parameter name="x"\n</ParameterList>\n')
        with self.assertRaisesRegex(EpapheError, "bad.xml: not well-formed XML"):
            read_deck(bad)
        with self.assertRaisesRegex(EpapheError, "absent.xml: cannot be read"):
            read_deck(os.path.join(self.dir, "absent.xml"))


if __name__ == "__main__":
    unittest.main()
