"""The hardened parser: hostile or broken XML gives a clear error and nothing else."""

from __future__ import annotations

import pytest

from homesim.errors import XMLInputError
from homesim.xmlio import MAX_DOCUMENT_BYTES, parse_bytes, parse_file, schema_from_text

BILLION_LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<lolz>&lol9;</lolz>"""


def test_billion_laughs_is_refused():
    with pytest.raises(XMLInputError, match="DOCTYPE"):
        parse_bytes(BILLION_LAUGHS, source="attack.xml")


def test_external_file_entity_is_refused_and_nothing_leaks(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET-CONTENT")
    doc = f'<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file://{secret}">]><r>&x;</r>'
    with pytest.raises(XMLInputError) as info:
        parse_bytes(doc, source="xxe.xml")
    assert "TOP-SECRET" not in str(info.value)


def test_network_entity_and_external_dtd_are_refused():
    for doc in (
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "http://127.0.0.1:9/evil">]><r>&x;</r>',
        '<?xml version="1.0"?><!DOCTYPE r SYSTEM "http://127.0.0.1:9/evil.dtd"><r/>',
        '<?xml version="1.0"?><!DOCTYPE r PUBLIC "-//X//Y" "http://127.0.0.1:9/y.dtd"><r/>',
    ):
        with pytest.raises(XMLInputError, match="DOCTYPE"):
            parse_bytes(doc, source="net.xml")


def test_oversized_document_is_refused_before_parsing():
    big = b"<a>" + b"x" * (MAX_DOCUMENT_BYTES + 1) + b"</a>"
    with pytest.raises(XMLInputError, match="larger than the limit"):
        parse_bytes(big, source="big.xml")


def test_deeply_nested_document_is_refused():
    depth = 10_000
    doc = b"<a>" * depth + b"</a>" * depth
    with pytest.raises(XMLInputError, match="big.xml:1: malformed XML"):
        parse_bytes(doc, source="big.xml")


def test_invalid_utf8_names_the_line():
    with pytest.raises(XMLInputError, match=r"bad\.xml:2: malformed XML"):
        parse_bytes(b"<a>\n<b>\xff\xfe</b></a>", source="bad.xml")


def test_truncated_document_names_the_file():
    with pytest.raises(XMLInputError, match=r"cut\.xml:3: malformed XML: Premature end"):
        parse_bytes(b"<a>\n<b>\n</b>", source="cut.xml")


def test_parse_file_reports_missing_files(tmp_path):
    with pytest.raises(XMLInputError, match="cannot read file"):
        parse_file(tmp_path / "nope.xml")


def test_well_formed_documents_parse_with_line_numbers():
    root = parse_bytes(b'<?xml version="1.0" encoding="UTF-8"?>\n<a>\n  <b x="\xc3\xa9"/>\n</a>')
    assert root[0].get("x") == "é"
    assert root[0].sourceline == 3


def test_schema_errors_name_schema_source_and_line():
    schema = schema_from_text(
        "count.xsd",
        '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">'
        '<xs:element name="count" type="xs:int"/></xs:schema>',
    )
    assert schema.is_valid(parse_bytes("<count>3</count>"))
    from homesim.errors import SchemaValidationError

    with pytest.raises(SchemaValidationError, match=r"in\.xml:2: does not satisfy schema count\.xsd: .*'x'"):
        schema.check(parse_bytes("\n<count>x</count>"), source="in.xml")


def test_the_parser_itself_is_hardened():
    """Bypass the DOCTYPE pre-check: the lxml parser must still be safe on its own."""
    from lxml import etree

    from homesim.xmlio import hardened_parser

    parser = hardened_parser()
    internal = b'<!DOCTYPE r [<!ENTITY e "EXPANDED">]><r>&e;</r>'
    root = etree.fromstring(internal, parser)
    assert "EXPANDED" not in etree.tostring(root).decode()  # entities stay unresolved
    # The external subset is not even asked for (no error, nothing loaded); the
    # docinfo check in parse_bytes refuses the DOCTYPE afterwards.
    root = etree.fromstring(b'<!DOCTYPE r SYSTEM "http://127.0.0.1:9/x.dtd"><r/>', parser)
    assert root.getroottree().docinfo.system_url == "http://127.0.0.1:9/x.dtd"
    depth = 300
    with pytest.raises(etree.XMLSyntaxError, match="depth"):
        etree.fromstring(b"<a>" * depth + b"</a>" * depth, parser)


def test_many_processing_instructions_do_not_blow_up_the_doctype_check():
    doc = b"<?pi x?>" * 5000 + b"<!---->" * 5000 + b"<r/>"
    assert parse_bytes(doc).tag == "r"
