"""Fixtures shared by the workbook's tests."""
import pytest

from rbcourse.workbook import exercises as ex


@pytest.fixture(params=["en", "fr"])
def language(request):
    """Each test that takes it runs once in English and once in French; the language before is restored."""
    before = ex.current()
    ex.langue(request.param)
    yield request.param
    ex.langue(before)
