"""The workbook's language switch (rbcourse.workbook.language): langue / language, current, the errors, and
the names it is exported under (ex.langue, rbcourse.workbook.langue)."""
import pytest

import rbcourse.workbook as workbook
from rbcourse.workbook import exercises as ex
from rbcourse.workbook import language


@pytest.fixture(autouse=True)
def back_to_english():
    yield
    language.langue("en")


def test_english_is_the_default_and_langue_switches():
    assert language.current() == "en"
    assert ex.langue("fr") == "fr" and ex.current() == "fr" and language.current() == "fr"
    assert ex.language("en") == "en" and ex.current() == "en"


def test_the_export_names():
    assert ex.langue is ex.language is workbook.langue is language.langue is language.language
    assert ex.current is workbook.current is language.current
    assert ex.LANGUAGES == workbook.LANGUAGES == ("en", "fr")
    for name in ("langue", "current", "LANGUAGES"):
        assert name in ex.__all__ and name in workbook.__all__
    assert "language" in ex.__all__
    assert workbook.language is language and hasattr(language, "text")      # the module is not shadowed


@pytest.mark.parametrize("bad", ["de", "FR", "", " fr", "french"])
def test_a_bad_code_names_the_parameter_and_the_allowed_values(bad):
    ex.langue("fr")
    with pytest.raises(ValueError) as e:
        ex.langue(bad)
    assert str(e.value) == f"langue: code must be one of 'en', 'fr', got {bad!r}"
    assert ex.current() == "fr"                      # unchanged by a refused call


@pytest.mark.parametrize("bad", [None, 1, b"fr", ["fr"], ("fr",)])
def test_a_code_that_is_not_a_string_is_refused_without_coercion(bad):
    with pytest.raises(ValueError, match=r"langue: code must be one of 'en', 'fr', got "):
        ex.langue(bad)
    assert ex.current() == "en"


def test_text_reads_the_table_of_the_active_language():
    table = {"en": {"hi": "hello {name}"}, "fr": {"hi": "bonjour {name}"}}
    assert language.text(table, "hi").format(name="Ann") == "hello Ann"
    ex.langue("fr")
    assert language.text(table, "hi").format(name="Ann") == "bonjour Ann"
