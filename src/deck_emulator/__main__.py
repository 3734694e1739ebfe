from deck_emulator.cli import main

raise SystemExit(main())
