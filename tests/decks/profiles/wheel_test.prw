# placeholder wheel profile for the deck reader tests (content not read)
