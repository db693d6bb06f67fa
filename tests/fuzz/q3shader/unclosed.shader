broken
{
  {
 map x.tga
