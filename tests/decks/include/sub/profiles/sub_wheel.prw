# placeholder profile, found relative to include/sub/
