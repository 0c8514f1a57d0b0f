from catc.cli import main

main()
