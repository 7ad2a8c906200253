"""The one error type for input the user gave us that does not meet the contract."""


class InputError(ValueError):
    """Bad input: names the file, the field and what was expected."""

    def __init__(self, file: object, field: str, expected: str, found: object = None):
        self.file, self.field, self.expected, self.found = str(file), field, expected, found
        text = f"{self.file}: field '{field}': expected {expected}"
        if found is not None:
            text += f", found {found!r}"
        super().__init__(text)
